function args = dentopo_options(pairs)
%DENTOPO_OPTIONS Name-value pairs as command line options: 'distance_type',
%   'geodesic' becomes --distance-type geodesic (underscores become dashes);
%   true is a bare flag; false and [] leave the option out; a cell array of
%   text becomes one comma-separated value; numbers are written with 17
%   significant digits, so they read back exactly.
if mod(numel(pairs), 2) ~= 0
  error('dentopo:options', 'options come in name-value pairs');
end
args = {};
for k = 1:2:numel(pairs)
  name = pairs{k};
  value = pairs{k + 1};
  if ~ischar(name) || isempty(name)
    error('dentopo:options', 'option names must be text');
  end
  flag = ['--' strrep(strrep(name, '_', '-'), '.', '-')];
  if isempty(value) || (islogical(value) && isscalar(value) && ~value)
    continue
  end
  if islogical(value) && isscalar(value)
    args{end + 1} = flag; %#ok<AGROW>
    continue
  end
  if isnumeric(value)
    if any(~isfinite(value(:)))
      error('dentopo:options', 'option %s wants finite numbers', flag);
    end
    text = strjoin(arrayfun(@dentopo_number, value(:)', 'UniformOutput', false), ',');
  elseif iscellstr(value)
    text = strjoin(value, ',');
  elseif ischar(value)
    text = value;
  else
    error('dentopo:options', 'option %s wants true/false, numbers or text', flag);
  end
  args = [args, {flag, text}]; %#ok<AGROW>
end
end

function text = dentopo_number(x)
% The shortest of 15, 16, 17 significant digits that reads back as X.
for digits = 15:17
  text = sprintf(sprintf('%%.%dg', digits), x);
  if str2double(text) == x
    return
  end
end
end
