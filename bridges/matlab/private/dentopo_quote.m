function quoted = dentopo_quote(text)
%DENTOPO_QUOTE One argument quoted for the shell that system() runs.
if ispc
  quoted = ['"' strrep(text, '"', '""') '"'];
else
  quoted = ['''' strrep(text, '''', '''\''''') ''''];
end
end
