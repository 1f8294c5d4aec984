function run_tests()
%RUN_TESTS Tests of ariaDNE.m and dentopo_batch.m, for GNU Octave and MATLAB.
%   Run from this folder: octave --eval run_tests (or run_tests in MATLAB).
%   Needs the dentopo command (DENTOPO or the PATH); the parity tests read
%   the values Python gives from the directory named by DENTOPO_PARITY_DIR
%   (tests/test_bridges.py writes them) and skip without it. Prints one line
%   per test and ends with an error when any failed.

here = fileparts(mfilename('fullpath'));
addpath(fileparts(here));
tests = {@test_batch_rows_and_columns, @test_options, @test_batch_usage_error, ...
         @test_ariadne_fields, @test_ariadne_errors, ...
         @test_parity_samples, @test_parity_shared, @test_parity_error_row, ...
         @test_no_command};
failed = 0;
skipped = 0;
for k = 1:numel(tests)
  name = func2str(tests{k});
  try
    reason = tests{k}();
    if ischar(reason) && ~isempty(reason)
      fprintf('SKIP %s: %s\n', name, reason);
      skipped = skipped + 1;
    else
      fprintf('ok   %s\n', name);
    end
  catch err
    failed = failed + 1;
    fprintf('FAIL %s: %s\n', name, err.message);
  end
end
fprintf('%d tests: %d passed, %d skipped, %d failed\n', numel(tests), ...
        numel(tests) - failed - skipped, skipped, failed);
if failed > 0
  error('run_tests:failed', '%d test(s) failed', failed);
end
end

% ---------------------------------------------------------------- helpers

function check(condition, varargin)
if ~condition
  error('run_tests:check', varargin{:});
end
end

function check_error(f, pattern)
try
  f();
catch err
  check(~isempty(regexp(err.message, pattern, 'once')), ...
        'wrong error: %s (expected /%s/)', err.message, pattern);
  return
end
error('run_tests:check', 'no error (expected /%s/)', pattern);
end

function d = relative_difference(got, want)
d = abs(got - want) ./ max(abs(want), realmin);
d(want == 0) = abs(got(want == 0));
d = max(d(:));
end

function path = sphere_ply(directory)
% An octahedron refined twice, pushed onto the unit sphere: 66 vertices.
v = [1 0 0; -1 0 0; 0 1 0; 0 -1 0; 0 0 1; 0 0 -1];
f = [1 3 5; 3 2 5; 2 4 5; 4 1 5; 3 1 6; 2 3 6; 4 2 6; 1 4 6];
for round = 1:2
  edges = sort([f(:, [1 2]); f(:, [2 3]); f(:, [3 1])], 2);
  [unique_edges, ~, which] = unique(edges, 'rows');
  middle = (v(unique_edges(:, 1), :) + v(unique_edges(:, 2), :)) / 2;
  middle = middle ./ repmat(sqrt(sum(middle .^ 2, 2)), 1, 3);
  m = size(v, 1) + reshape(which, [], 3);
  v = [v; middle]; %#ok<AGROW>
  f = [f(:, 1) m(:, 1) m(:, 3); m(:, 1) f(:, 2) m(:, 2); ...
       m(:, 3) m(:, 2) f(:, 3); m(:, 1) m(:, 2) m(:, 3)];
end
path = fullfile(directory, 'sphere.ply');
fid = fopen(path, 'w');
fprintf(fid, ['ply\nformat ascii 1.0\nelement vertex %d\nproperty float x\n' ...
              'property float y\nproperty float z\nelement face %d\n' ...
              'property list uchar int vertex_indices\nend_header\n'], size(v, 1), size(f, 1));
fprintf(fid, '%.9f %.9f %.9f\n', v');
fprintf(fid, '3 %d %d %d\n', (f - 1)');
fclose(fid);
end

function directory = scratch()
directory = tempname();
mkdir(directory);
end

function rows = as_rows(T)
% dentopo_batch's result as a struct array (MATLAB returns a table).
if isstruct(T)
  rows = T;
else
  rows = table2struct(T);
end
end

function value = text_of(x)
% A text cell of a table row (MATLAB: a 1x1 cell) or struct field as char.
if iscell(x)
  value = x{1};
else
  value = x;
end
end

function [dir, reason] = parity_dir()
dir = getenv('DENTOPO_PARITY_DIR');
reason = '';
if isempty(dir)
  reason = 'DENTOPO_PARITY_DIR not set (tests/test_bridges.py sets it)';
end
end

function want = parity_rows(set, distance_type)
% Rows of expected.csv (plain: no quoted fields) as a struct array.
dir = parity_dir();
lines = regexp(strtrim(fileread(fullfile(dir, 'expected.csv'))), '\r?\n', 'split');
want = struct('file', {}, 'dne', {}, 'positive_dne', {}, 'negative_dne', {});
for k = 2:numel(lines)
  cells = strsplit(lines{k}, ',');
  if strcmp(cells{1}, set) && strcmp(cells{2}, distance_type)
    want(end + 1) = struct('file', cells{3}, 'dne', str2double(cells{4}), ...
                           'positive_dne', str2double(cells{5}), ...
                           'negative_dne', str2double(cells{6})); %#ok<AGROW>
  end
end
end

function reason = check_parity(set)
[~, reason] = parity_dir();
if ~isempty(reason)
  return
end
want = parity_rows(set, 'euclidean');
if isempty(want)
  reason = sprintf('no %s rows in the parity table (shared meshes absent?)', set);
  return
end
% dentopo_batch: the command's columns
rows = as_rows(dentopo_batch({want.file}));
worst = 0;
for k = 1:numel(want)
  row = rows(strcmp({rows.file}, want(k).file));
  check(numel(row) == 1 && strcmp(text_of(row.status), 'ok'), 'no ok row for %s', want(k).file);
  worst = max([worst, relative_difference(row.dne, want(k).dne), ...
               relative_difference(row.positive_dne, want(k).positive_dne), ...
               relative_difference(row.negative_dne, want(k).negative_dne)]);
end
% ariaDNE.m, Euclidean, on the first mesh (each call starts the command: the
% batch above has checked every mesh); negativeDNE <= 0 as MATLAB's signDNE
for k = 1
  H = ariaDNE(want(k).file, 0.08, struct('distInfo', 'Euclidean'));
  worst = max([worst, relative_difference(H.dne, want(k).dne), ...
               relative_difference(H.positiveDNE, want(k).positive_dne), ...
               relative_difference(-H.negativeDNE, want(k).negative_dne)]);
end
% ariaDNE.m's default: geodesic distances, as the original
geodesic = parity_rows(set, 'geodesic');
for k = 1:numel(geodesic)
  H = ariaDNE(geodesic(k).file);
  worst = max([worst, relative_difference(H.dne, geodesic(k).dne), ...
               relative_difference(H.positiveDNE, geodesic(k).positive_dne), ...
               relative_difference(-H.negativeDNE, geodesic(k).negative_dne)]);
end
fprintf(['Octave parity, %s (%d meshes; ariaDNE.m on 1 Euclidean, %d geodesic): ' ...
         'max relative difference %.3g\n'], set, numel(want), numel(geodesic), worst);
check(worst <= 1e-12, 'relative difference %g > 1e-12', worst);
end

% ------------------------------------------------------------------ tests

function reason = test_batch_rows_and_columns()
reason = '';
d = scratch();
good = sphere_ply(d);
bad = fullfile(d, 'bad, "quoted".ply');
fid = fopen(bad, 'w');
fprintf(fid, 'not a mesh\n');
fclose(fid);
rows = as_rows(dentopo_batch({good, bad}));
check(numel(rows) == 2, 'expected 2 rows, got %d', numel(rows));
expected = {'file', 'dne', 'positive_dne', 'negative_dne', 'surface_area', ...
            'positive_surface_area', 'negative_surface_area', 'vertices', 'faces', ...
            'bandwidth', 'cutoff', 'distance_type', 'sign_method', 'method', 'protocol', ...
            'seconds', 'status', 'error', 'warnings'};
check(isequal(fieldnames(rows)', expected), 'columns: %s', strjoin(fieldnames(rows)', ','));
ok = rows(strcmp({rows.status}, 'ok'));
check(strcmp(ok.file, good), 'file column: %s', ok.file);
check(ok.vertices == 66, 'vertices: %d', ok.vertices);
check(isempty(ok.error), 'error on an ok row');
check(abs(ok.positive_dne + ok.negative_dne - ok.dne) <= 1e-12 * ok.dne, 'split');
failed = rows(strcmp({rows.status}, 'error'));
check(strcmp(failed.file, bad), 'file column of the error row: %s', failed.file);
check(~isempty(strfind(failed.error, 'bad, "quoted".ply')), 'message: %s', failed.error);
check(isnan(failed.dne), 'dne of an error row');
end

function reason = test_options()
% Options reach the command: dentopo_batch's by name, ariaDNE's Options as
% the same command line options (the same numbers, to the last bit).
reason = '';
good = sphere_ply(scratch());
rows = as_rows(dentopo_batch(good, 'bandwidth', 0.1, 'distance_type', 'geodesic', ...
                             'cutoff', 0.001, 'metrics', 'ariadne'));
check(rows.bandwidth == 0.1 && rows.cutoff == 0.001, 'bandwidth, cutoff');
check(strcmp(text_of(rows.distance_type), 'geodesic'), 'distance type');
H = ariaDNE(good, 0.1, struct('distInfo', 'Geodesic', 'cutThresh', 0.001));
check(H.dne == rows.dne && -H.negativeDNE == rows.negative_dne, ...
      'ariaDNE with distInfo ''Geodesic'', cutThresh: %.17g vs %.17g', H.dne, rows.dne);
signdne = as_rows(dentopo_batch(good, 'columns', 'signdne'));
check(isequal(fieldnames(signdne)', {'File', 'DNE', 'positive_DNE', 'negative_DNE', ...
      'surface_area', 'positive_surface_area', 'negative_surface_area'}), 'signdne columns');
end

function reason = test_batch_usage_error()
reason = '';
good = sphere_ply(scratch());
check_error(@() dentopo_batch(good, 'no_such_option', 1), ...
            'unrecognized arguments: --no-such-option');
check_error(@() dentopo_batch(good, 'output', 'x.csv'), 'returns the table');
end

function reason = test_ariadne_fields()
reason = '';
good = sphere_ply(scratch());
H = ariaDNE(good, 0.1, struct('distInfo', 'Euclidean'));
names = {'dne', 'positiveDNE', 'negativeDNE', 'localDNE', 'curvature', 'surfaceArea', ...
         'vertices'};
check(isequal(fieldnames(H)', names), 'fields: %s', strjoin(fieldnames(H)', ','));
check(isequal(size(H.localDNE), [66 1]) && isequal(size(H.curvature), [66 1]), 'sizes');
check(isequal(size(H.vertices), [66 3]), 'vertices size');
check(H.negativeDNE <= 0, 'negativeDNE is zero or below');
check(abs(sum(abs(H.localDNE)) - H.dne) <= 1e-12 * H.dne, 'dne = sum |localDNE|');
check(abs(sum(H.localDNE(H.localDNE >= 0)) - H.positiveDNE) <= 1e-12 * H.dne, 'positive');
check(abs(sum(H.localDNE(H.localDNE < 0)) - H.negativeDNE) <= 1e-12 * H.dne, 'negative');
check(all(sign(H.curvature) == sign(H.localDNE) | H.localDNE == 0), 'signs agree');
check(H.surfaceArea > 11 && H.surfaceArea < 4 * pi, 'area of an inscribed sphere: %g', H.surfaceArea);
end

function reason = test_ariadne_errors()
reason = '';
d = scratch();
good = sphere_ply(d);
check_error(@() ariaDNE(good, 0.08, struct('distance', zeros(66))), 'Options.distance');
check_error(@() ariaDNE(good, 0.08, struct('distInfo', 'Manhattan')), 'Geodeisic');
check_error(@() ariaDNE(d), 'directory');
bad = fullfile(d, 'bad.ply');
fid = fopen(bad, 'w');
fprintf(fid, 'not a mesh\n');
fclose(fid);
check_error(@() ariaDNE(bad), 'could not read mesh file ''.*bad.ply'': not a PLY file');
end

function reason = test_parity_samples()
reason = check_parity('samples');
end

function reason = test_parity_shared()
reason = check_parity('shared');
end

function reason = test_parity_error_row()
[dir, reason] = parity_dir();
if ~isempty(reason)
  return
end
bad = fileread(fullfile(dir, 'bad_file.txt'));
message = fileread(fullfile(dir, 'bad_error.txt'));
rows = as_rows(dentopo_batch(bad));
check(strcmp(text_of(rows.file), bad), 'file: %s', text_of(rows.file));
check(strcmp(text_of(rows.status), 'error'), 'status');
check(strcmp(text_of(rows.error), message), 'message changed: %s', text_of(rows.error));
end

function reason = test_no_command()
reason = '';
saved = getenv('DENTOPO');
saved_path = getenv('PATH');
restore = onCleanup(@() restore_command(saved, saved_path)); %#ok<NASGU>
dentopo_command(fullfile(tempdir(), 'no-such-dentopo'));
setenv('DENTOPO', '');
setenv('PATH', tempdir());
check_error(@() dentopo_command(), 'pip install dentopo');
end

function restore_command(saved, saved_path)
setenv('DENTOPO', saved);
setenv('PATH', saved_path);
dentopo_command('');
end
