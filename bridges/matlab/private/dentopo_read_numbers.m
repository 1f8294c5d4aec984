function [names, data] = dentopo_read_numbers(path)
%DENTOPO_READ_NUMBERS A CSV of numbers with one header line: the column
%   names and the numbers (dlmread reads the shortest-repr text exactly).
fid = fopen(path, 'r');
if fid < 0
  error('dentopo:table', 'could not open %s', path);
end
header = fgetl(fid);
fclose(fid);
names = strsplit(strtrim(header), ',');
data = dlmread(path, ',', 1, 0);
end
