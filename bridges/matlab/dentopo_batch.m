function T = dentopo_batch(files, varargin)
%DENTOPO_BATCH Measure mesh files with the dentopo command: one row per file.
%   T = DENTOPO_BATCH(FILES) runs dentopo on FILES (a file, directory or glob
%   pattern as text, or a cell array of them) and returns its table: in
%   MATLAB a table, in GNU Octave (which has no tables) an N-by-1 struct
%   array, with the command's columns as fields: file, dne, positive_dne,
%   negative_dne, surface_area, positive_surface_area,
%   negative_surface_area, vertices, faces, bandwidth, cutoff,
%   distance_type, sign_method, method, protocol, seconds, status, error,
%   warnings.
%
%   Every file gets a row: a file that fails has status 'error', its error
%   text unchanged, and NaN for its numbers (error is '' on rows that
%   succeeded). negative_dne is the concave part as a magnitude (>= 0), as in
%   the command's table; ariaDNE.m reports it as in MATLAB's signDNE (<= 0).
%
%   T = DENTOPO_BATCH(FILES, NAME, VALUE, ...) passes options to the
%   command: 'bandwidth', 0.08 becomes --bandwidth 0.08, 'distance_type',
%   'geodesic' becomes --distance-type geodesic (underscores become dashes);
%   true is a bare flag, false or [] leaves it out; a cell array of text
%   becomes one comma-separated value. In particular:
%       'metrics'  metrics to compute; 'ariadne' (the command's default) is
%                  not passed, so it works with every version of the command
%       'columns'  'signdne' for the published signDNE command's columns
%                  (which leave failed files out)
%       'jobs'     worker processes (0: every core)
%   See 'dentopo --help'.
%
%   A usage error (a bad option, no mesh files found) is an error with the
%   command's message. The command is found by DENTOPO_COMMAND.
%
%   Example:
%       T = dentopo_batch('scans/', 'bandwidth', 0.08, 'jobs', 2);
%       T = dentopo_batch({'a.ply', 'b.ply'}, 'columns', 'signdne');

if ischar(files)
  files = {files};
elseif isempty(files)
  files = {};
end
if ~iscellstr(files)
  error('dentopo:files', 'dentopo_batch: FILES must be text or a cell array of text');
end
for k = 1:2:numel(varargin)
  if ischar(varargin{k}) && any(strcmp(varargin{k}, {'output', 'o'}))
    error('dentopo:options', 'dentopo_batch returns the table; write it yourself');
  end
  if ischar(varargin{k}) && strcmp(varargin{k}, 'metrics') && k < numel(varargin)
    metrics = varargin{k + 1};
    if (ischar(metrics) && strcmpi(metrics, 'ariadne')) || ...
       (iscellstr(metrics) && all(strcmpi(metrics, 'ariadne')))
      varargin{k + 1} = [];
    end
  end
end
[workdir, cleanup] = dentopo_workdir(); %#ok<ASGLU> removes workdir on return
args = [{'--quiet', '--output', '-'}, dentopo_options(varargin)];
if ~isempty(files)  % none: e.g. 'samples', true alone
  args = [args, {'--'}, files(:)'];
end
rows = dentopo_read_table(dentopo_run(args, workdir));
if exist('OCTAVE_VERSION', 'builtin') == 0 && exist('struct2table', 'file') == 2
  T = struct2table(rows, 'AsArray', true);
else
  T = rows;
end
end
