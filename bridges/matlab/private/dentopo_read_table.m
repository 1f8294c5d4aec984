function rows = dentopo_read_table(path)
%DENTOPO_READ_TABLE The command's CSV table as an N-by-1 struct array.
%   Fields as read from the header (every character outside A-Z, a-z, 0-9
%   and _ replaced by _). Every cell is read as text first, so an error
%   message with commas, quotes or line breaks comes through unchanged; a
%   column whose every non-empty cell is a number becomes numbers (empty:
%   NaN), read with str2double (exact for the shortest-repr text the command
%   writes); other columns stay text ('' where empty). A cell that begins
%   with an apostrophe had one put there by the command (so that a
%   spreadsheet does not run a name such as '=HYPERLINK(...).ply' as a
%   formula): exactly one is removed, as dentopo's read_table does.
text = fileread(path);
tokens = regexp(text, '("(?:[^"]|"")*"|[^,"\r\n]*)(,|\r\n|\n|$)', 'tokens');
records = {};
current = {};
for k = 1:numel(tokens)
  field = tokens{k}{1};
  if ~isempty(field) && field(1) == '"'
    field = strrep(field(2:end - 1), '""', '"');
  end
  current{end + 1} = field; %#ok<AGROW>
  if ~strcmp(tokens{k}{2}, ',')
    if ~(numel(current) == 1 && isempty(current{1}))
      records{end + 1} = current; %#ok<AGROW>
    end
    current = {};
  end
end
if isempty(records)
  error('dentopo:table', 'dentopo wrote no table');
end
names = regexprep(records{1}, '[^A-Za-z0-9_]', '_');
body = records(2:end);
n = numel(body);
columns = cell(1, numel(names));
for j = 1:numel(names)
  cells = cell(n, 1);
  for i = 1:n
    if j <= numel(body{i})
      cells{i} = body{i}{j};
      if ~isempty(cells{i}) && cells{i}(1) == ''''
        cells{i} = cells{i}(2:end);
      end
    else
      cells{i} = '';
    end
  end
  empty = cellfun(@isempty, cells);
  numbers = str2double(cells);
  is_text = any(strcmp(names{j}, {'file', 'File', 'status', 'error', 'warnings', ...
                                  'distance_type', 'sign_method', 'method', ...
                                  'orientation', 'orient', 'protocol'}));
  if ~is_text && all(~isnan(numbers(~empty)) | strcmpi(cells(~empty), 'nan'))
    numbers(empty) = NaN;
    columns{j} = num2cell(numbers);
  else
    columns{j} = cells;
  end
end
if n == 0
  rows = cell2struct(cell(numel(names), 0), names, 1);
else
  pairs = [names; columns];
  rows = struct(pairs{:});
  rows = rows(:);
end
end
