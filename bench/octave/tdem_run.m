% Run Yao & Choi's toroidal density-equalizing map (TDEM) on one of its own
% example meshes and export the result for ../shared/tools/param-eval.
% This script only calls the peer's functions (it copies none of its code):
%   git clone https://github.com/garyptchoi/toroidal-density-equalizing-map TDEM_DIR
%   octave --no-gui -q bench/octave/tdem_run.m TDEM_DIR example_bob OUT_DIR
% The steps before TDEM() follow the peer's demo_TDEM_parameterization.m (slice
% along the stored cut ee, order the four corners, periodic rectangular start),
% with its parameters: population = surface face areas, dt 0.1, epsilon 1e-2,
% max_iter 500.
% Writes OUT_DIR/NAME_orig.obj (v_ori, f_ori: the closed surface),
% OUT_DIR/NAME_tdem.obj (same v and faces, vt = TDEM's planar uv, one row per
% sliced vertex) and OUT_DIR/NAME_tdem.txt (times, iterations and the
% distortion measured on TDEM's own target, the torus of revolution in 3D).
max_recursion_depth(100000);  % the peer's meshboundaries walks the cut boundary recursively
args = argv();
tdem_dir = args{1}; name = args{2}; out = args{3};
addpath(fullfile(tdem_dir, 'code'));
addpath(fullfile(fileparts(mfilename('fullpath')), 'compat'));  % triangulation stand-in
load(fullfile(tdem_dir, 'data', [name '.mat']));   % v_ori f_ori ee R r

t_start = tic;
[f, v, parent_id] = slice_mesh(f_ori, v_ori, ee);
bd = meshboundaries(f);
bdy_index = bd{1};
vid = find(parent_id == mode(parent_id));
pos = arrayfun(@(x) find(bdy_index == x), vid(1:4));
corner = bdy_index(sort(pos));
id = find(bdy_index == corner(1));
bdy_index = bdy_index([id:end, 1:id-1]);
id2 = find(bdy_index == corner(2)); id3 = find(bdy_index == corner(3));
len1 = sum(sqrt(sum((v(bdy_index(2:id2),:) - v(bdy_index(1:id2-1),:)).^2, 2)));
len2 = sum(sqrt(sum((v(bdy_index(id2+1:id3),:) - v(bdy_index(id2:id3-1),:)).^2, 2)));
if len1 < len2
  corner = corner([2;3;4;1]);
end
uv0 = rectangular_map_periodic2(v, f, corner, 2*pi*R, 2*pi*r);
map0 = toroidal_projection(uv0, R, r);
population = face_area(f, v);
t_init = toc(t_start);

t_flow0 = tic;
[map, uv] = TDEM(map0, f, population, R, r, 0.1, 1e-2, 500);
t_flow = toc(t_flow0);

% Distortion on TDEM's own target (the torus of revolution in 3D):
% per face r = (torus face area share) / (surface face area share),
% per vertex r = (share of the torus area of the faces around it) /
%                (share of the surface area of the faces around it).
At = face_area(f, map); As = face_area(f_ori, v_ori);
rf = (At / sum(At)) ./ (As / sum(As));
nv = size(v_ori, 1);
Vt = accumarray(f_ori(:), repmat(At, 3, 1), [nv 1]);
Vs = accumarray(f_ori(:), repmat(As, 3, 1), [nv 1]);
rv = (Vt / sum(Vt)) ./ (Vs / sum(Vs));
% folds in the flat (u,v) rectangle: signed area <= 0
e1 = uv(f(:,2),:) - uv(f(:,1),:); e2 = uv(f(:,3),:) - uv(f(:,1),:);
sa = e1(:,1).*e2(:,2) - e1(:,2).*e2(:,1);

fid = fopen(fullfile(out, [name '_tdem.txt']), 'w');
fprintf(fid, 'mesh %s V %d F %d R %g r %g\n', name, nv, size(f_ori,1), R, r);
fprintf(fid, 'time_init %.3f time_tdem %.3f\n', t_init, t_flow);
fprintf(fid, 'torus3d_face_mean_abs_r_minus_1 %.6g\n', mean(abs(rf - 1)));
fprintf(fid, 'torus3d_face_mean_abs_log_r %.6g\n', mean(abs(log(rf))));
fprintf(fid, 'torus3d_vertex_mean_abs_log_r %.6g\n', mean(abs(log(rv))));
fprintf(fid, 'torus3d_face_r_min %.6g max %.6g\n', min(rf), max(rf));
fprintf(fid, 'uv_folds %d of %d (signed area <= 0)\n', sum(sa <= 0), numel(sa));
fclose(fid);

fid = fopen(fullfile(out, [name '_orig.obj']), 'w');
fprintf(fid, 'v %.17g %.17g %.17g\n', v_ori');
fprintf(fid, 'f %d %d %d\n', f_ori');
fclose(fid);
fid = fopen(fullfile(out, [name '_tdem.obj']), 'w');
fprintf(fid, 'v %.17g %.17g %.17g\n', v_ori');
fprintf(fid, 'vt %.17g %.17g\n', uv');
fprintf(fid, 'f %d/%d %d/%d %d/%d\n', [parent_id(f(:,1)), f(:,1), parent_id(f(:,2)), f(:,2), parent_id(f(:,3)), f(:,3)]');
fclose(fid);
