# atlas.sh - workflow.atlas: manifest rows with command atlas (data/genus2.obj, genus 2; data/ellipsoid.obj,
# genus 0) and one bad input run through the cohort workflow: status 0, no folds, per-face <= 0.02 and
# vertex <= 0.005 in cohort.tsv, the same figures as param-eval (--coords vt --domain plane) when
# ../shared has it, one distortion value per vertex, a preview, a view linked from cohort.md; the bad
# row gets status 2 and empty products without stopping the others.
. "$(dirname "$0")/lib.sh"
d=$WORK/atlas
rm -rf "$d" && mkdir -p "$d" || fail "cannot make $d"
for m in genus2 ellipsoid; do
  [ -f "$SRC/data/$m.obj" ] || skip "$SRC/data/$m.obj is missing (run au_mkdata to generate data/)"
done
{
  printf 'id\tinput\tcommand\toptions\tdensity\tattribute\n'
  printf 'genus2\t%s\tatlas\t\t\t\n' "$SRC/data/genus2.obj"
  printf 'ellipsoid\t%s\tatlas\t--max-cones 8\t\t\n' "$SRC/data/ellipsoid.obj"
  printf 'bad_index\t%s\tatlas\t\t\t\n' "$SRC/tests/cli/bad/index_range.obj"
} > "$d/manifest.tsv"
run_workflow "$d/out" "$d/manifest.tsv" "$d/run.log" || { tail -30 "$d/run.log" >&2; fail "snakemake exited $? (the bad row must not fail the workflow)"; }
PE=$SHARED/tools/param-eval
[ -x "$PE" ] || { echo "note: no $PE, cohort figures not compared with param-eval"; PE=""; }
$PY - "$d/out" "$SRC" "$PE" <<'PYEOF' || fail "cohort of atlas rows (above)"
import csv, json, os, subprocess, sys
out, src, pe = sys.argv[1:4]
sys.path.insert(0, os.path.join(src, "workflow", "scripts"))
import meshio_np
rows = {r["id"]: r for r in csv.DictReader(open(os.path.join(out, "cohort.tsv")), delimiter="\t")}
bad = []
def check(ok, msg):
    if not ok:
        bad.append(msg)
md = open(os.path.join(out, "cohort.md")).read()
for i in ("genus2", "ellipsoid"):
    r, s = rows[i], os.path.join(out, "surfaces", i)
    print({k: r[k] for k in ("id", "command", "status", "V", "F", "steps", "folds", "r_mean_abs_dev", "vertex_logr_mean_abs")})
    check(r["command"] == "atlas" and r["status"] == "0" and r["folds"] == "0", f"{i}: status/folds {r}")
    check(float(r["r_mean_abs_dev"]) <= 0.02 and float(r["vertex_logr_mean_abs"]) <= 0.005, f"{i}: errors {r}")
    X, F = meshio_np.read_mesh(os.path.join(src, "data", i + ".obj"))
    check((int(r["V"]), int(r["F"])) == (len(X), len(F)), f"{i}: V, F {r['V']}, {r['F']} for {len(X)}, {len(F)}")
    check(int(r["steps"]) > 0 and float(r["seconds"]) > 0, f"{i}: steps {r['steps']}, seconds {r['seconds']}")
    VT, FT = meshio_np.read_obj_vt(os.path.join(s, "map.obj"))
    check(len(FT) == len(F) and VT.min() >= 0 and VT.max() <= 1, f"{i}: map vt not in [0,1]^2 for every face")
    import nibabel.freesurfer
    dist = nibabel.freesurfer.read_morph_data(os.path.join(s, "distortion.curv"))
    check(len(dist) == len(X) and 0 < abs(dist).mean() < 0.05, f"{i}: {len(dist)} distortion values, mean |d| {abs(dist).mean()}")
    png = open(os.path.join(s, "preview.png"), "rb").read(8)
    check(png == b"\x89PNG\r\n\x1a\n", f"{i}: preview.png is not a PNG")
    check(os.path.getsize(os.path.join(s, "view.html")) > 0 and f"surfaces/{i}/view.html" in md, f"{i}: no view linked")
    if pe:
        res = subprocess.run([pe, os.path.join(src, "data", i + ".obj"), os.path.join(s, "map.obj"), "--coords", "vt",
                              "--domain", "plane", "--json"], capture_output=True, text=True)
        ref = json.loads(res.stdout)
        for k in ("folds", "r_mean_abs_dev", "vertex_logr_mean_abs", "upsilon_mean_abs", "lambda_mean", "r_cv"):
            check(abs(float(r[k]) - ref[k]) <= 1e-9 * max(1.0, abs(ref[k])), f"{i}: {k} {r[k]} vs param-eval {ref[k]}")
r, s = rows["bad_index"], os.path.join(out, "surfaces", "bad_index")
print({k: r[k] for k in ("id", "status", "error")})
check(r["status"] == "2" and "out of range" in r["error"], f"bad_index: status {r['status']}, error {r['error']!r}")
check(all(os.path.getsize(os.path.join(s, f)) == 0 for f in ("map.obj", "preview.png", "distortion.curv")),
      "bad_index: products not empty")
for b in bad:
    print("FAIL:", b)
sys.exit(1 if bad else 0)
PYEOF
echo "workflow.atlas: ok"
