function va = vertexAttachments(T, vc)
% Stand-in for MATLAB's triangulation/vertexAttachments: for each vertex in
% vc, the indices of its faces ordered as consecutive neighbours around it
% (face j+1 shares with face j the edge from the vertex to face j's corner
% before it; on the boundary the walk starts at the face with a free edge).
f = T.ConnectivityList;
va = cell(numel(vc), 1);
for i = 1:numel(vc)
  [rows, col] = find(f == vc(i));
  nxt = f(sub2ind(size(f), rows, mod(col, 3) + 1));     % corner after vc
  prv = f(sub2ind(size(f), rows, mod(col + 1, 3) + 1)); % corner before vc
  start = find(~ismember(nxt, prv), 1);
  if isempty(start), start = 1; end
  order = zeros(numel(rows), 1); order(1) = start;
  for j = 2:numel(rows)
    k = find(nxt == prv(order(j - 1)), 1);
    if isempty(k), order = order(1:j - 1); break; end
    order(j) = k;
  end
  va{i} = rows(order)';
end
end
