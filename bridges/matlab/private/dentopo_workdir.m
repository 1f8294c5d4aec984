function [workdir, cleanup] = dentopo_workdir()
%DENTOPO_WORKDIR A new temporary directory, removed (with everything in it)
%   when CLEANUP is cleared, also after an error.
workdir = tempname();
[ok, msg] = mkdir(workdir);
if ~ok
  error('dentopo:tempdir', 'could not create a temporary directory %s: %s', workdir, msg);
end
cleanup = onCleanup(@() dentopo_remove(workdir));
end

function dentopo_remove(path)
% Remove a directory and what it holds (rmdir(path, 's') asks for
% confirmation in Octave).
entries = dir(path);
for k = 1:numel(entries)
  name = entries(k).name;
  if strcmp(name, '.') || strcmp(name, '..')
    continue
  end
  inner = fullfile(path, name);
  if entries(k).isdir
    dentopo_remove(inner);
  else
    delete(inner);
  end
end
rmdir(path);
end
