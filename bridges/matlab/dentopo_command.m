function cmd = dentopo_command(setting)
%DENTOPO_COMMAND The dentopo command the bridge runs.
%   CMD = DENTOPO_COMMAND() returns the command line (shell-quoted) that
%   runs dentopo: the one set with DENTOPO_COMMAND(SETTING) in this session,
%   else the DENTOPO environment variable, else 'dentopo' on the PATH; the
%   first that answers 'dentopo --version' is used. When none does, an
%   error says how to install it.
%
%   DENTOPO_COMMAND(SETTING) sets the command for this session: the path of
%   the program (spaces allowed), or a command line split on white space
%   such as 'python3 -m dentopo'. DENTOPO_COMMAND('') clears it.
%
%   Example:
%       dentopo_command('/home/me/venvs/dentopo/bin/dentopo');

persistent chosen working
if nargin == 1
  if ~ischar(setting)
    error('dentopo:command', 'dentopo_command: the setting must be text');
  end
  chosen = setting;
  working = '';
  if nargout > 0
    cmd = dentopo_command();
  end
  return
end
if ~isempty(working)
  cmd = working;
  return
end
sources = {};
values = {};
if ~isempty(chosen)
  sources{end + 1} = 'dentopo_command(...)';
  values{end + 1} = chosen;
end
env = getenv('DENTOPO');
if ~isempty(env)
  sources{end + 1} = 'the DENTOPO environment variable';
  values{end + 1} = env;
end
sources{end + 1} = 'the PATH';
values{end + 1} = 'dentopo';
problems = {};
for k = 1:numel(values)
  candidate = dentopo_shell_command(values{k});
  [status, said] = system([candidate ' --version 2>&1']);
  said = strtrim(said);
  if status == 0 && strncmp(said, 'dentopo', 7)
    if ~isempty(problems)
      warning('dentopo:command', 'dentopo: using %s from %s; %s', values{k}, ...
              sources{k}, strjoin(problems, '; '));
    end
    working = candidate;
    cmd = candidate;
    return
  end
  if numel(said) > 200
    said = [said(1:200) '...'];
  end
  problems{end + 1} = sprintf('%s (''%s'') does not work: exit status %d %s', ...
                              sources{k}, values{k}, status, said);
end
error('dentopo:notFound', ['the dentopo command was not found (%s). Install it with ' ...
      '''pip install .'' in a clone of dentopo or ''pip install dentopo'' from PyPI, ' ...
      'then put it on the PATH, set the DENTOPO environment ' ...
      'variable to the program (e.g. DENTOPO=/path/to/venv/bin/dentopo), or call ' ...
      'dentopo_command(''/path/to/venv/bin/dentopo'').'], strjoin(problems, '; '));
end

function cmd = dentopo_shell_command(value)
% An existing file is one program (spaces and all); anything else is split on
% white space ('python3 -m dentopo').
if exist(value, 'file') == 2
  parts = {value};
else
  parts = strsplit(strtrim(value));
end
cmd = strjoin(cellfun(@dentopo_quote, parts, 'UniformOutput', false), ' ');
end
