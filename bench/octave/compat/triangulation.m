function T = triangulation(f, v)
% Minimal stand-in for MATLAB's triangulation class, which Octave 7 lacks:
% a struct with ConnectivityList, Points and freeBoundary (the directed
% edges a->b of the faces whose reverse b->a belongs to no face), which is
% all the TDEM code asks of it (with vertexAttachments.m next to this file).
n = max(size(v, 1), max(f(:)));
E = [f(:, [1 2]); f(:, [2 3]); f(:, [3 1])];
S = sparse(E(:, 1), E(:, 2), 1, n, n);
free = full(S(sub2ind([n n], E(:, 2), E(:, 1)))) == 0;
T = struct('ConnectivityList', f, 'Points', v, 'freeBoundary', E(free, :));
end
