/* view.js - the `authalic view` page: a surface and its map side by side, coloured by the map's
 * distortion. three.js is inlined in the page (the #au-three block, imported through a blob URL), the
 * mesh and its figures are in #au-data (written by au_view_html, common/au_view.c): positions quantized
 * to 16 bits over their bounding box, faces and per-face values as little-endian binary arrays in
 * base64. Nothing is fetched. */
const THREE = await import(URL.createObjectURL(new Blob([document.getElementById('au-three').textContent],
  {type: 'text/javascript'})));
const D = JSON.parse(document.getElementById('au-data').textContent);
const $ = id => document.getElementById(id);

/* ---------------------------------------------------------------- decoding */

function bytes(b64) {
  const s = atob(b64), n = s.length, u = new Uint8Array(n);
  for (let i = 0; i < n; i++) u[i] = s.charCodeAt(i);
  return u.buffer;
}
/* Positions: dim values per row, q / 65535 of the box from min over scale. */
function positions(P) {
  const q = new Uint16Array(bytes(P.q)), out = new Float32Array(q.length), d = P.dim;
  for (let i = 0; i < q.length; i++) out[i] = P.min[i % d] + (q[i] / 65535) * P.scale[i % d];
  return out;
}
const nf = D.nf, F = new Uint32Array(bytes(D.F));
const X = positions(D.X), M = positions(D.M), mdim = D.M.dim;
const Ft = D.Ft ? new Uint32Array(bytes(D.Ft)) : F;
const logr = new Float32Array(bytes(D.logr)), lam = new Float32Array(bytes(D.lam));
const attr = D.attr ? new Float32Array(bytes(D.attr.v)) : null;
const sphere = D.kind === 'sphere', lattice = D.lattice;

/* ---------------------------------------------------------------- scales */

function quantile(a, p) {
  const v = Float32Array.from(a).filter(Number.isFinite).sort(); /* typed: a numeric sort, fast on 1M values */
  return v.length ? v[Math.min(v.length - 1, Math.floor(p * v.length))] : 0;
}
function absArray(a) { const b = new Float32Array(a.length); for (let i = 0; i < a.length; i++) b[i] = Math.abs(a[i]); return b; }
/* The colour scales are symmetric about exact (log r = 0) and reach the 99th percentile of |log r|,
 * so the most squeezed faces are at the saturated end. */
const Rr = Math.max(quantile(absArray(logr), 0.99), 0.02), Rl = Math.max(quantile(lam, 0.99), 0.02);
const attrLo = attr ? quantile(attr, 0.02) : 0, attrHi = attr ? quantile(attr, 0.98) : 1;
const DIV = [[33, 102, 172], [146, 197, 222], [247, 247, 247], [244, 165, 130], [178, 24, 43]];
const SEQ = [[247, 247, 247], [188, 189, 220], [117, 107, 177], [63, 0, 125]];
const VIR = [[68, 1, 84], [59, 82, 139], [33, 145, 140], [94, 201, 98], [253, 231, 37]];
function ramp(stops, t) {
  t = Math.min(1, Math.max(0, t)) * (stops.length - 1);
  const k = Math.min(stops.length - 2, Math.floor(t)), f = t - k, a = stops[k], b = stops[k + 1];
  return [0, 1, 2].map(i => Math.round(a[i] + f * (b[i] - a[i])));
}
const css = c => `rgb(${c[0]},${c[1]},${c[2]})`;
const glslStops = (name, s) => `vec3 ${name}(float t) { t = clamp(t, 0.0, 1.0) * ${(s.length - 1).toFixed(1)};\n` +
  s.slice(0, -1).map((c, k) => `  if (t <= ${(k + 1).toFixed(1)}) return mix(vec3(${c.map(x => (x / 255).toFixed(5))}), ` +
    `vec3(${s[k + 1].map(x => (x / 255).toFixed(5))}), t - ${k.toFixed(1)});`).join('\n') +
  `\n  return vec3(${s[s.length - 1].map(x => (x / 255).toFixed(5))});\n}\n`;

/* ---------------------------------------------------------------- geometry */

/* Non-indexed triangles (three corners per face), so a face carries its own value and id. */
const surfPos = new Float32Array(9 * nf), mapPos = new Float32Array(9 * nf);
const val = new Float32Array(3 * nf), fid = new Float32Array(3 * nf);
for (let f = 0; f < nf; f++)
  for (let k = 0; k < 3; k++) {
    const c = 3 * f + k, v = F[c], m = Ft[c];
    for (let j = 0; j < 3; j++) surfPos[3 * c + j] = X[3 * v + j];
    mapPos[3 * c] = M[mdim * m], mapPos[3 * c + 1] = M[mdim * m + 1], mapPos[3 * c + 2] = mdim === 3 ? M[3 * m + 2] : 0;
    fid[c] = f;
  }
const tuvAttr = new THREE.BufferAttribute(mapPos, 3), valAttr = new THREE.BufferAttribute(val, 1);
const fidAttr = new THREE.BufferAttribute(fid, 1);
function geometry(pos) {
  const g = new THREE.BufferGeometry();
  g.setAttribute('position', new THREE.BufferAttribute(pos, 3));
  g.setAttribute('tuv', tuvAttr), g.setAttribute('val', valAttr), g.setAttribute('fid', fidAttr);
  g.computeBoundingSphere();
  return g;
}
const surfGeom = geometry(surfPos), mapGeom = geometry(mapPos);

/* Checkerboard cells: on the sphere equal-area cells in (longitude, z); on a plane squares of a
 * twentieth of the map's (or the lattice's) size. */
const mb = new THREE.Box3().setFromBufferAttribute(mapGeom.getAttribute('position'));
const planeCell = lattice ? Math.hypot(lattice[0][0], lattice[0][1]) / 12 : Math.max(mb.max.x - mb.min.x, mb.max.y - mb.min.y) / 20;

const vertexShader = `
attribute vec3 tuv; attribute float val; attribute float fid;
varying vec3 vT; varying float vVal; varying vec3 vView; varying float vFid;
void main() {
  vT = tuv; vVal = val; vFid = fid;
  vec4 mv = modelViewMatrix * vec4(position, 1.0);
  vView = mv.xyz;
  gl_Position = projectionMatrix * mv;
}`;
const fragmentShader = glslStops('divRamp', DIV) + glslStops('seqRamp', SEQ) + glslStops('virRamp', VIR) + `
uniform int mode; uniform float lit; uniform float lo; uniform float hi; uniform float cell; uniform bool sphereT;
varying vec3 vT; varying float vVal; varying vec3 vView; varying float vFid;
void main() {
  vec3 c;
  if (mode == 9) {
    float id = floor(vFid + 0.5) + 1.0;
    gl_FragColor = vec4(mod(id, 256.0), mod(floor(id / 256.0), 256.0), floor(id / 65536.0), 255.0) / 255.0;
    return;
  }
  if (mode == 2) {
    vec2 u;
    if (sphereT) {
      vec3 p = normalize(vT);
      u = vec2((atan(p.y, p.x) / 6.2831853 + 0.5) * 32.0, (p.z * 0.5 + 0.5) * 16.0);
    } else u = vT.xy / cell;
    float k = mod(floor(u.x) + floor(u.y), 2.0);
    c = mix(vec3(0.93, 0.9, 0.82), vec3(0.2, 0.36, 0.55), k);
  } else if (vVal != vVal) c = vec3(0.5);
  else if (mode == 0) c = divRamp((vVal - lo) / (hi - lo));
  else if (mode == 1) c = seqRamp((vVal - lo) / (hi - lo));
  else c = virRamp((vVal - lo) / (hi - lo));
  if (lit > 0.0) {
    vec3 n = normalize(cross(dFdx(vView), dFdy(vView)));
    c *= 1.0 - lit + lit * abs(n.z);
  }
  gl_FragColor = vec4(c, 1.0);
}`;
function material(lit) {
  return new THREE.ShaderMaterial({vertexShader, fragmentShader, side: THREE.DoubleSide,
    uniforms: {mode: {value: 0}, lit: {value: lit}, lo: {value: -Rr}, hi: {value: Rr}, cell: {value: planeCell},
      sphereT: {value: sphere}}});
}
const surfMat = material(0.6), mapMat = material(sphere ? 0.25 : 0);

/* ---------------------------------------------------------------- scenes */

const canvas = $('au-canvas');
const renderer = new THREE.WebGLRenderer({canvas, antialias: true, preserveDrawingBuffer: true});
renderer.setPixelRatio(window.devicePixelRatio || 1);
renderer.setClearColor(0x202124);
renderer.autoClear = false;

function fitGroup(geom) {
  const s = geom.boundingSphere, g = new THREE.Group();
  g.userData.center = s.center.clone(), g.userData.radius = s.radius || 1;
  return g;
}
const surfScene = new THREE.Scene(), mapScene = new THREE.Scene();
const surfMesh = new THREE.Mesh(surfGeom, surfMat);
const surfGroup = fitGroup(surfGeom);
surfMesh.position.copy(surfGroup.userData.center).multiplyScalar(-1);
surfGroup.add(surfMesh), surfScene.add(surfGroup);
const surfScale = 1 / surfGroup.userData.radius;
surfGroup.scale.setScalar(surfScale);

const mapGroup = new THREE.Group(), mapMeshes = [];
const tiles = lattice ? [-1, 0, 1].flatMap(i => [-1, 0, 1].map(j => [i, j])) : [[0, 0]];
for (const [i, j] of tiles) {
  const m = new THREE.Mesh(mapGeom, mapMat);
  if (lattice) m.position.set(i * lattice[0][0] + j * lattice[1][0], i * lattice[0][1] + j * lattice[1][1], 0);
  m.userData.central = i === 0 && j === 0;
  mapMeshes.push(m), mapGroup.add(m);
}
const mapCentral = mapMeshes.find(m => m.userData.central);
if (lattice) { /* a fundamental domain, outlined about the middle of the central tile */
  const L = lattice, o = [(mb.min.x + mb.max.x - L[0][0] - L[1][0]) / 2, (mb.min.y + mb.max.y - L[0][1] - L[1][1]) / 2];
  const pts = [[0, 0], [1, 0], [1, 1], [0, 1], [0, 0]].map(([a, b]) =>
    new THREE.Vector3(o[0] + a * L[0][0] + b * L[1][0], o[1] + a * L[0][1] + b * L[1][1], 0.001));
  mapGroup.add(new THREE.Line(new THREE.BufferGeometry().setFromPoints(pts), new THREE.LineBasicMaterial({color: 0x000000})));
}
mapScene.add(mapGroup);
/* The flat map's extent: the 3 x 3 tiles of a torus, else its box. */
const mapBox = mb.clone();
if (lattice) for (const m of mapMeshes) mapBox.union(mb.clone().translate(m.position));
const mapCenter = mapBox.getCenter(new THREE.Vector3()), mapSize = mapBox.getSize(new THREE.Vector3());

const surfCam = new THREE.PerspectiveCamera(35, 1, 0.01, 100);
const mapCam = sphere ? new THREE.PerspectiveCamera(35, 1, 0.01, 100) : new THREE.OrthographicCamera(-1, 1, 1, -1, -10, 10);
const DIST = 1 / Math.sin((35 / 2) * Math.PI / 180) * 1.08;

/* Markers: where the pointer is, and the same point of the surface on the other side. */
function marker(r) {
  const m = new THREE.Mesh(new THREE.SphereGeometry(r, 16, 8), new THREE.MeshBasicMaterial({color: 0xffd400, depthTest: false}));
  m.renderOrder = 10, m.visible = false;
  return m;
}
const surfMark = marker(0.015 / surfScale), mapMark = marker(sphere ? 0.015 : 0.008 * Math.max(mapSize.x, mapSize.y));
surfMesh.add(surfMark), mapCentral.add(mapMark);

/* ---------------------------------------------------------------- view state */

const view = {};
function reset() {
  surfGroup.quaternion.identity(), surfCam.position.set(0, 0, DIST), surfCam.lookAt(0, 0, 0);
  mapGroup.quaternion.identity(), mapGroup.position.set(0, 0, 0);
  if (sphere) mapCam.position.set(0, 0, DIST), mapCam.lookAt(0, 0, 0);
  else {
    mapGroup.position.set(-mapCenter.x, -mapCenter.y, 0);
    view.half = 0.54 * Math.max(mapSize.x / view.aspect, mapSize.y), view.panX = 0, view.panY = 0;
  }
  draw();
}
function layout() {
  const w = window.innerWidth, h = window.innerHeight;
  renderer.setSize(w, h, false);
  view.w = w, view.h = h, view.aspect = (w / 2) / h;
  surfCam.aspect = view.aspect, surfCam.updateProjectionMatrix();
  if (sphere) mapCam.aspect = view.aspect, mapCam.updateProjectionMatrix();
}
function orthoUpdate() {
  if (sphere) return;
  const h = view.half, w = h * view.aspect;
  Object.assign(mapCam, {left: view.panX - w, right: view.panX + w, top: view.panY + h, bottom: view.panY - h});
  mapCam.position.set(0, 0, 5), mapCam.updateProjectionMatrix();
}
let pending = false;
function draw() {
  orthoUpdate();
  const w = view.w, h = view.h;
  renderer.setScissorTest(true);
  for (const [scene, cam, x] of [[surfScene, surfCam, 0], [mapScene, mapCam, w / 2]]) {
    renderer.setViewport(x, 0, w / 2, h), renderer.setScissor(x, 0, w / 2, h);
    renderer.clear(), renderer.render(scene, cam);
  }
  renderer.setScissorTest(false);
}
function redraw() { if (!pending) pending = true, requestAnimationFrame(() => { pending = false; draw(); }); }

/* ---------------------------------------------------------------- colour modes */

const modes = ['area', 'angle', 'checker', 'attr'];
function setMode(name) {
  if (name === 'attr' && !attr) name = 'area';
  $('au-mode').value = name;
  const k = modes.indexOf(name);
  const per = name === 'angle' ? lam : logr;
  if (name === 'attr') for (let c = 0; c < 3 * nf; c++) val[c] = attr[F[c]];
  else for (let c = 0; c < 3 * nf; c++) val[c] = per[(c / 3) | 0];
  valAttr.needsUpdate = true;
  const [lo, hi] = name === 'angle' ? [0, Rl] : name === 'attr' ? [attrLo, attrHi > attrLo ? attrHi : attrLo + 1] : [-Rr, Rr];
  for (const m of [surfMat, mapMat]) Object.assign(m.uniforms.mode, {value: k}), m.uniforms.lo.value = lo, m.uniforms.hi.value = hi;
  legend(name, lo, hi);
  redraw();
}
function legend(name, lo, hi) {
  const stops = name === 'angle' ? SEQ : name === 'attr' ? VIR : DIV, bar = $('au-legend-bar');
  $('au-legend').style.display = name === 'checker' ? 'none' : '';
  bar.style.background = `linear-gradient(to right, ${stops.map(css).join(', ')})`;
  const fmt = x => Math.abs(x) >= 100 || (Math.abs(x) < 0.01 && x !== 0) ? x.toExponential(2) : x.toFixed(3);
  const [a, b, c] = name === 'area' ? [`squeezed: r = ${fmt(Math.exp(lo))}`, 'exact: r = 1', `stretched: r = ${fmt(Math.exp(hi))}`]
    : name === 'angle' ? ['conformal: \u039b = 0', '', `\u039b = ${fmt(hi)}`]
    : [fmt(lo), D.attr ? D.attr.name : '', fmt(hi)];
  $('au-lo').textContent = a, $('au-mid').textContent = b, $('au-hi').textContent = c;
}

/* ---------------------------------------------------------------- figures and histograms */

function figures() {
  const s = D.stats, t = [['vertices', D.nv], ['faces', nf], ['folds', s.folds],
    ['per-face mean |r\u22121|', s.per_face.toPrecision(3)], ['vertex mean |log r|', s.vertex.toPrecision(3)],
    ['steps', s.steps >= 0 ? s.steps : '\u2013'], ['time', s.seconds >= 0 ? s.seconds.toFixed(2) + ' s' : '\u2013']];
  if (s.excluded) t.push(['degenerate faces', s.excluded]);
  $('au-figs').innerHTML = '<table>' + t.map(([k, v]) => `<tr><td>${k}</td><td>${v}</td></tr>`).join('') + '</table>';
  $('au-title').textContent = D.title || 'authalic view';
  if (D.title) document.title = D.title + ' - authalic view';
}
function histogram(id, a, lo, hi, stops, label) {
  const cv = $(id), g = cv.getContext('2d'), W = cv.width, H = cv.height, nb = 60, n = new Float64Array(nb);
  for (const x of a) if (Number.isFinite(x)) n[Math.min(nb - 1, Math.max(0, Math.floor((x - lo) / (hi - lo) * nb)))]++;
  const top = Math.max(...n) || 1;
  g.clearRect(0, 0, W, H);
  for (let k = 0; k < nb; k++) {
    const bh = (H - 16) * n[k] / top;
    g.fillStyle = css(ramp(stops, (k + 0.5) / nb)), g.fillRect(k * W / nb, H - 14 - bh, W / nb - 0.5, bh);
  }
  g.fillStyle = '#ddd', g.font = '11px sans-serif';
  g.fillText(label, 2, 10), g.fillText(lo.toFixed(2), 0, H - 2), g.fillText(hi.toFixed(2), W - 26, H - 2);
}

/* ---------------------------------------------------------------- picking and linked cursors */

const pickRT = new THREE.WebGLRenderTarget(1, 1), pickPx = new Uint8Array(4);
const pickMat = material(0);
pickMat.uniforms.mode.value = 9;
/* The face under page pixel (x, y) and the point on it: GPU picking (the face id drawn as a colour into
 * one pixel), then the ray met with that one triangle. */
function pick(x, y) {
  const left = x < view.w / 2, scene = left ? surfScene : mapScene, cam = left ? surfCam : mapCam;
  const lx = left ? x : x - view.w / 2, W = view.w / 2, H = view.h;
  const shown = [surfMark.visible, mapMark.visible];
  surfMark.visible = mapMark.visible = false; /* the markers carry no face ids */
  cam.setViewOffset(W, H, lx, y, 1, 1);
  scene.overrideMaterial = pickMat, renderer.setRenderTarget(pickRT), renderer.setViewport(0, 0, 1, 1);
  renderer.setClearColor(0x000000, 0), renderer.clear(), renderer.render(scene, cam);
  renderer.readRenderTargetPixels(pickRT, 0, 0, 1, 1, pickPx);
  renderer.setRenderTarget(null), renderer.setClearColor(0x202124, 1), scene.overrideMaterial = null, cam.clearViewOffset();
  [surfMark.visible, mapMark.visible] = shown;
  const f = pickPx[0] + 256 * pickPx[1] + 65536 * pickPx[2] - 1;
  if (f < 0 || f >= nf) return null;
  const ray = new THREE.Raycaster();
  ray.setFromCamera(new THREE.Vector2(lx / W * 2 - 1, 1 - y / H * 2), cam);
  const pos = left ? surfPos : mapPos, meshes = left ? [surfMesh] : mapMeshes;
  for (const mesh of meshes) {
    mesh.updateMatrixWorld();
    const P = [0, 1, 2].map(k => new THREE.Vector3().fromArray(pos, 9 * f + 3 * k).applyMatrix4(mesh.matrixWorld));
    const hit = ray.ray.intersectTriangle(P[0], P[1], P[2], false, new THREE.Vector3());
    if (hit) return {f, left, bary: new THREE.Triangle(P[0], P[1], P[2]).getBarycoord(hit, new THREE.Vector3()), mesh};
  }
  return {f, left, bary: new THREE.Vector3(1 / 3, 1 / 3, 1 / 3), mesh: meshes[0]};
}
function corner(pos, f, b) {
  const p = new THREE.Vector3();
  for (let k = 0; k < 3; k++) p.addScaledVector(new THREE.Vector3().fromArray(pos, 9 * f + 3 * k), b.getComponent(k));
  return p;
}
function hover(x, y) {
  const h = pick(x, y);
  surfMark.visible = mapMark.visible = !!h;
  if (h) {
    surfMark.position.copy(corner(surfPos, h.f, h.bary));
    const q = corner(mapPos, h.f, h.bary);
    if (sphere) q.normalize().multiplyScalar(1.003);
    mapMark.position.copy(q);
    const a = attr ? `  ${D.attr.name} ${(h.bary.x * attr[F[3 * h.f]] + h.bary.y * attr[F[3 * h.f + 1]] + h.bary.z * attr[F[3 * h.f + 2]]).toPrecision(4)}` : '';
    $('au-hover').textContent = `face ${h.f}: r ${Math.exp(logr[h.f]).toPrecision(4)}  log r ${logr[h.f].toPrecision(3)}  \u039b ${lam[h.f].toPrecision(3)}${a}`;
  } else $('au-hover').textContent = '';
  draw();
}

/* ---------------------------------------------------------------- interaction */

let drag = null;
canvas.addEventListener('pointerdown', e => { drag = {x: e.clientX, y: e.clientY, left: e.clientX < view.w / 2}; canvas.setPointerCapture(e.pointerId); });
canvas.addEventListener('pointerup', () => { drag = null; });
function rotate(group, dx, dy) {
  const q = new THREE.Quaternion(), k = 4 / view.h;
  q.setFromEuler(new THREE.Euler(dy * k, dx * k, 0, 'XYZ'));
  group.quaternion.premultiply(q);
}
/* Picking draws the scene once more: at most once a frame, for the latest pointer position. */
let hoverAt = null;
canvas.addEventListener('pointermove', e => {
  if (!drag) {
    if (!hoverAt) requestAnimationFrame(() => { const [x, y] = hoverAt; hoverAt = null; hover(x, y); });
    hoverAt = [e.clientX, e.clientY];
    return;
  }
  const dx = e.clientX - drag.x, dy = e.clientY - drag.y;
  drag.x = e.clientX, drag.y = e.clientY;
  if (drag.left) rotate(surfGroup, dx, dy);
  else if (sphere) rotate(mapGroup, dx, dy);
  else view.panX -= dx * 2 * view.half / view.h, view.panY += dy * 2 * view.half / view.h;
  redraw();
});
canvas.addEventListener('wheel', e => {
  e.preventDefault();
  const s = Math.exp(e.deltaY * 0.001), left = e.clientX < view.w / 2;
  if (left) surfCam.position.z = Math.min(20, Math.max(0.05, surfCam.position.z * s));
  else if (sphere) mapCam.position.z = Math.min(20, Math.max(1.01, 1 + (mapCam.position.z - 1) * s));
  else view.half *= s;
  redraw();
}, {passive: false});
function savePNG() {
  draw();
  const a = document.createElement('a');
  a.href = canvas.toDataURL('image/png'), a.download = (D.title || 'authalic-view').replace(/[^\w.-]+/g, '_') + '.png';
  a.click();
}
addEventListener('keydown', e => {
  if (e.target.tagName === 'SELECT') return;
  if (e.key === 'r') reset();
  else if (e.key === 'p') savePNG();
  else if ('1234'.includes(e.key)) setMode(modes[+e.key - 1]);
});
$('au-reset').onclick = reset, $('au-png').onclick = savePNG;
$('au-mode').onchange = e => setMode(e.target.value);

/* ---------------------------------------------------------------- start */

if (!attr) $('au-mode-attr').remove();
else $('au-mode-attr').textContent = 'attribute: ' + D.attr.name;
figures();
histogram('au-hist-r', logr, -Math.max(Rr, 1e-3) * 1.5, Math.max(Rr, 1e-3) * 1.5, DIV, 'per-face log r');
histogram('au-hist-l', lam, 0, Rl * 1.5, SEQ, 'per-face angle distortion \u039b');
layout();
const opts = new URLSearchParams(location.hash.slice(1));
setMode(opts.get('mode') || (attr ? 'attr' : 'area'));
reset();
if (opts.has('probe')) probe();
/* A resize (the first layout of a headless browser's window too) lays the page out afresh. */
addEventListener('resize', () => { layout(); reset(); if (opts.has('probe')) probe(); });

/* #probe (for tests; also redone on resize): turn the map to its most squeezed face, zoom until its inscribed circle is
 * some pixels across, and say on the console where it is drawn and which colour the scale gives it. */
function probe() {
  let f0 = -1;
  for (let f = 0; f < nf; f++) if (Number.isFinite(logr[f]) && (f0 < 0 || logr[f] < logr[f0])) f0 = f;
  /* The face's incentre, the point farthest from its edges, and its inradius e. */
  const P = [0, 1, 2].map(k => new THREE.Vector3().fromArray(mapPos, 9 * f0 + 3 * k));
  const len = [0, 1, 2].map(k => P[(k + 1) % 3].distanceTo(P[(k + 2) % 3])), per = len[0] + len[1] + len[2];
  const c = new THREE.Vector3();
  for (let k = 0; k < 3; k++) c.addScaledVector(P[k], len[k] / per);
  const e = new THREE.Vector3().subVectors(P[1], P[0]).cross(new THREE.Vector3().subVectors(P[2], P[0])).length() / per;
  const px = 8; /* the inradius wanted in pixels at least */
  if (sphere) {
    mapGroup.quaternion.setFromUnitVectors(c.clone().normalize(), new THREE.Vector3(0, 0, 1));
    const fl = view.h / 2 / Math.tan(35 / 2 * Math.PI / 180);
    mapCam.position.z = Math.min(DIST, Math.max(1.02, 1 + fl * e / px));
  } else {
    view.half = Math.min(view.half, Math.max(e * view.h / 2 / px, 1e-6));
    view.panX = c.x - mapCenter.x, view.panY = c.y - mapCenter.y;
  }
  /* Every colour mode drawn once (their errors would show on the console), then the area's. */
  for (const m of modes) setMode(m), draw();
  setMode('area');
  draw();
  mapCentral.updateMatrixWorld();
  const s = c.clone().applyMatrix4(mapCentral.matrixWorld).project(mapCam);
  const x = view.w / 2 + (s.x + 1) / 2 * view.w / 2, y = (1 - s.y) / 2 * view.h;
  /* The linked cursor's path: the face picked there, and the surface point marked for it. */
  hover(x, y);
  const on = surfMark.visible && Number.isFinite(surfMark.position.x);
  console.log(`AUTHALIC_PICK ${pick(x, y) ? pick(x, y).f : -1} marked ${on}`);
  surfMark.visible = mapMark.visible = false, $('au-hover').textContent = '';
  draw();
  const col = ramp(DIV, (logr[f0] + Rr) / (2 * Rr));
  console.log(`AUTHALIC_PROBE ${x.toFixed(1)} ${y.toFixed(1)} ${col.join(' ')} face ${f0} logr ${logr[f0]}`);
}
console.log(`AUTHALIC_READY ${nf} faces, drawn ${Math.round(performance.now())} ms after the page began to load`);
