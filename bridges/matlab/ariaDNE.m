function H = ariaDNE(meshname, bandwidth, Options)
%ARIADNE ariaDNE of a mesh file, with the original MATLAB interface.
%   H = ARIADNE(MESHNAME, BANDWIDTH, OPTIONS) computes ariaDNE (Shan et al.
%   2019) and its convex/concave split for the mesh in MESHNAME (PLY, OBJ,
%   STL, OFF, ...) by running the dentopo command (see DENTOPO_COMMAND), so
%   that scripts written for the original ariaDNE.m run unchanged.
%
%   BANDWIDTH   kernel bandwidth epsilon on the unit-area scale (default
%               0.08, as in the original).
%   OPTIONS     a struct; every field optional:
%     distInfo  'Geodeisic' (the original's spelling, and its default:
%               shortest paths along mesh edges), 'Geodesic' (the same) or
%               'Euclidean' (straight-line distance; dentopo's and signDNE's
%               default). Case does not matter.
%     cutThresh neighbours whose kernel weight is <= cutThresh are ignored
%               (default 0).
%     distance  a precomputed distance matrix: NOT supported (an error): the
%               dentopo command cannot take one. Use the Python function
%               dentopo.ariaDNE(mesh, precomputed_dist=D) instead.
%
%   H has the fields (per-vertex ones are columns, one value per vertex of
%   the cleaned mesh):
%     dne           ariaDNE: the sum of |localDNE|
%     positiveDNE   the convex part: the sum of the positive localDNE
%     negativeDNE   the concave part as MATLAB's signDNE reports it: the sum
%                   of the negative localDNE, so zero or below (dne =
%                   positiveDNE - negativeDNE; dentopo's tables give it as a
%                   magnitude, >= 0)
%     localDNE      signed local DNE: curvature times the vertex's share of
%                   the unit-scaled area (the original's localDNE is the
%                   unsigned value, abs(H.localDNE))
%     curvature     signed local curvature: + convex, - concave (the
%                   original's curvature is unsigned, abs(H.curvature))
%     surfaceArea   the mesh's surface area, in the file's units squared
%     vertices      the cleaned mesh's vertex coordinates (N-by-3), in the
%                   file's units (an addition: the rows of the fields above)
%
%   Differences from the original: the mesh is cleaned and measured as
%   dentopo does (see its README); the signs come from dentopo's
%   sign-oriented extension (signDNE); a file that cannot be measured is an
%   error with dentopo's message.
%
%   Example:
%       H = ariaDNE('tooth.ply', 0.08, struct('distInfo', 'Euclidean'));
%       fprintf('DNE %.4f = %.4f + %.4f\n', H.dne, H.positiveDNE, -H.negativeDNE);

if nargin < 1 || ~ischar(meshname) || isempty(meshname)
  error('ariaDNE:meshname', 'ariaDNE: MESHNAME must be the path of a mesh file');
end
if nargin < 2 || isempty(bandwidth)
  bandwidth = 0.08;
end
if ~isnumeric(bandwidth) || ~isscalar(bandwidth) || ~isreal(bandwidth)
  error('ariaDNE:bandwidth', 'ariaDNE: BANDWIDTH must be a number');
end
if nargin < 3 || isempty(Options)
  Options = struct();
end
if ~isstruct(Options)
  error('ariaDNE:Options', 'ariaDNE: OPTIONS must be a struct');
end
if isfield(Options, 'distance') && ~isempty(Options.distance)
  error('ariaDNE:distance', ['ariaDNE: Options.distance (a precomputed distance ' ...
        'matrix) is not supported here: the dentopo command cannot take one. Use the ' ...
        'Python function dentopo.ariaDNE(mesh, precomputed_dist=D) instead, or leave ' ...
        'Options.distance out and set Options.distInfo.']);
end
distInfo = 'Geodeisic';
if isfield(Options, 'distInfo') && ~isempty(Options.distInfo)
  distInfo = Options.distInfo;
end
switch lower(distInfo)
  case {'geodeisic', 'geodesic'}
    distance_type = 'geodesic';
  case 'euclidean'
    distance_type = 'euclidean';
  otherwise
    error('ariaDNE:distInfo', ['ariaDNE: Options.distInfo must be ''Geodeisic'', ' ...
          '''Geodesic'' or ''Euclidean''; got ''%s'''], distInfo);
end
cutThresh = 0;
if isfield(Options, 'cutThresh') && ~isempty(Options.cutThresh)
  cutThresh = Options.cutThresh;
end
if exist(meshname, 'dir') == 7
  error('ariaDNE:meshname', 'ariaDNE: ''%s'' is a directory; give one mesh file', meshname);
end

[workdir, cleanup] = dentopo_workdir(); %#ok<ASGLU> removes workdir on return
values = fullfile(workdir, 'values');
args = [{'--quiet', '--output', '-', '--per-vertex', values, '--per-vertex-format', 'csv'}, ...
        dentopo_options({'bandwidth', bandwidth, 'cutoff', cutThresh, ...
                         'distance_type', distance_type}), {'--', meshname}];
row = dentopo_read_table(dentopo_run(args, workdir));
if numel(row) ~= 1
  error('ariaDNE:meshname', 'ariaDNE: ''%s'' gave %d rows; give one mesh file', ...
        meshname, numel(row));
end
if ~strcmp(row.status, 'ok')
  error('ariaDNE:failed', '%s', row.error);
end
written = dir(fullfile(values, '*.dentopo.csv'));
if numel(written) ~= 1
  error('ariaDNE:failed', 'ariaDNE: expected one per-vertex CSV from dentopo, found %d', ...
        numel(written));
end
[columns, data] = dentopo_read_numbers(fullfile(values, written(1).name));
column = @(name) data(:, strcmp(columns, name));

H = struct();
H.dne = row.dne;
H.positiveDNE = row.positive_dne;
H.negativeDNE = -row.negative_dne;
H.localDNE = column('local_dne');
H.curvature = column('local_curvature');
H.surfaceArea = row.surface_area;
H.vertices = [column('x'), column('y'), column('z')];
end
