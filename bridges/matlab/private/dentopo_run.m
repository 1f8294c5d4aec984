function table_file = dentopo_run(args, workdir)
%DENTOPO_RUN Run dentopo with ARGS (a cell array of text) in WORKDIR.
%   Returns the file holding its standard output (the table as CSV). Exit
%   status 0 (all ok) and 1 (some file failed: its row says why) are not
%   errors here; anything else (2: usage error, 130: interrupted) is an
%   error with the command's own message.
cmd = dentopo_command();
table_file = fullfile(workdir, 'stdout.csv');
messages = fullfile(workdir, 'stderr.txt');
quoted = cellfun(@dentopo_quote, args, 'UniformOutput', false);
line = sprintf('%s %s > %s 2> %s', cmd, strjoin(quoted, ' '), ...
               dentopo_quote(table_file), dentopo_quote(messages));
status = system(line);
info = dir(table_file);
if (status == 0 || status == 1) && ~isempty(info) && info.bytes > 0
  return
end
said = '';
if exist(messages, 'file') == 2
  said = dentopo_message(fileread(messages));
end
switch status
  case 2
    what = 'usage error';
  case 130
    what = 'interrupted';
  otherwise
    what = 'failed';
end
if isempty(said)
  error('dentopo:command', 'dentopo %s (exit status %d)', what, status);
end
error('dentopo:command', 'dentopo %s (exit status %d): %s', what, status, said);
end

function said = dentopo_message(text)
% The command's message without argparse's usage block.
lines = regexp(text, '\r?\n', 'split');
keep = {};
in_usage = false;
for k = 1:numel(lines)
  line = lines{k};
  if strncmp(line, 'usage:', 6)
    in_usage = true;
    continue
  end
  if in_usage && ~isempty(line) && isspace(line(1))
    continue
  end
  in_usage = false;
  if ~isempty(strtrim(line))
    keep{end + 1} = line; %#ok<AGROW>
  end
end
said = strjoin(keep, sprintf('\n'));
end
