/* fuzz_read.c - libFuzzer harness for the mesh readers: the bytes become a file with the extension
 * AU_FUZZ_EXT (".obj", ".off", ".ply", ".stl", ".white" or ".gii"; one fuzz target per format) that
 * au_io_read reads. For the neuroimaging formats (AU_FUZZ_FORMAT set: FreeSurfer, found by its
 * magic number under any name, and GIfTI through giftiio) the same bytes also go through
 * au_io_read_scalars (curv files, .shape.gii), and the round trip writes in that format with the
 * input's metadata (the FreeSurfer footer, the GIfTI metadata).
 *
 * Besides "no crash, no leak, no undefined behaviour" (the sanitizers' part), it checks what the
 * readers promise: an error leaves *out NULL and says what is wrong in one non-empty line; a
 * success holds a mesh with positive counts and every index in range, which au_mesh_validate then
 * checks like the CLI does (for the sphere, and for any topology); and for the formats the writer
 * knows, writing the mesh and reading it back gives the same vertices and faces. A broken promise
 * aborts, which libFuzzer reports as a crash. */
#define _POSIX_C_SOURCE 200809L

#include <math.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "au_io.h"
#include "au_mesh.h"

#ifndef AU_FUZZ_EXT
#error "define AU_FUZZ_EXT, e.g. -DAU_FUZZ_EXT=\".obj\""
#endif

static char dir[64], in_path[96], out_path[96];

/* The scratch folder lives in memory when possible (tmpfs makes the writer's fsync cheap). */
static void setup(void) {
  const char *base = access("/dev/shm", W_OK) == 0 ? "/dev/shm" : "/tmp";
  snprintf(dir, sizeof dir, "%s/au_fuzz_read.XXXXXX", base);
  if (!mkdtemp(dir)) abort();
  snprintf(in_path, sizeof in_path, "%s/in%s", dir, AU_FUZZ_EXT);
  snprintf(out_path, sizeof out_path, "%s/out%s", dir, AU_FUZZ_EXT);
}

static void cleanup(void) {
  unlink(in_path);
  unlink(out_path);
  rmdir(dir);
}

int LLVMFuzzerInitialize(int *argc, char ***argv) {
  (void)argc, (void)argv;
  setup();
  atexit(cleanup);
  return 0;
}

/* An error message: non-empty, NUL-terminated inside the buffer, one line. */
static void check_msg(const au_msg *msg) {
  const char *nul = memchr(msg->text, '\0', sizeof msg->text);
  if (!nul || nul == msg->text || memchr(msg->text, '\n', (size_t)(nul - msg->text))) abort();
}

static int same_double(double a, double b) { return a == b || (isnan(a) && isnan(b)); }

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size) {
  FILE *fp = fopen(in_path, "wb");
  if (!fp) abort();
  if (size > 0 && fwrite(data, 1, size, fp) != size) abort();
  if (fclose(fp) != 0) abort();

  au_mesh *m = (au_mesh *)&m; /* not NULL, so that "an error leaves *out NULL" is tested */
  au_msg msg;
#ifdef AU_FUZZ_FORMAT
  double *vals = (double *)&m;
  int count = -1;
  memset(&msg, 'x', sizeof msg);
  au_status sst = au_io_read_scalars(in_path, 0, &vals, &count, &msg);
  if (sst != AU_OK) {
    if (vals != NULL || sst > 0) abort();
    check_msg(&msg);
  } else {
    if (!vals || count <= 0) abort();
    for (int i = 0; i < count; i++)
      if (!isfinite(vals[i])) abort();
    free(vals);
  }
#endif
  au_io_meta *meta = (au_io_meta *)&m;
  memset(&msg, 'x', sizeof msg); /* not NUL-terminated, so that a missing message is caught */
  au_status st = au_io_read_meta(in_path, &m, &meta, &msg);
  if (st != AU_OK) {
    if (m != NULL || meta != NULL || st > 0) abort();
    check_msg(&msg);
    return 0;
  }
  if (!m || m->nv <= 0 || m->nf <= 0 || !m->X || !m->F) abort();
  for (long j = 0; j < 3L * m->nf; j++)
    if (m->F[j] < 0 || m->F[j] >= m->nv) abort();

  /* Validation as the sphere command asks for it, and with no topological expectation. */
  au_mesh_expect ex = au_mesh_expect_default();
  ex.command = "sphere";
  for (int pass = 0; pass < 2; pass++) {
    au_topo *t = NULL;
    memset(&msg, 'x', sizeof msg);
    st = au_mesh_validate(m, &ex, &t, &msg);
    if (st < 0) {
      if (t) abort();
      check_msg(&msg);
    } else {
      if (!t || t->nv != m->nv || t->nf != m->nf || t->ne <= 0) abort();
      au_topo_free(&t);
      if (t) abort();
    }
    ex.loops = -1, ex.genus = -1, ex.command = NULL;
  }

  /* Round trip through the writer (STL is read-only). FreeSurfer and GIfTI store float32: a position
   * beyond it (or not finite) is refused, and the others come back as their float32 values. */
  au_io_write_opts o = au_io_write_opts_default();
  o.meta = meta;
#ifdef AU_FUZZ_FORMAT
  o.format = AU_FUZZ_FORMAT;
  int fits = 1;
  for (long i = 0; i < 3L * m->nv; i++) fits &= isfinite(m->X[i]) && fabs(m->X[i]) <= 3.4028234663852886e38;
#else
  const int fits = 1;
#endif
  if (o.format != AU_IO_FORMAT_AUTO || au_io_can_write(out_path)) {
    memset(&msg, 'x', sizeof msg);
    st = au_io_write(out_path, m, m->X, &o, &msg);
    if (!fits && st == AU_E_FORMAT) check_msg(&msg);
    else if (st != AU_OK) abort();
    au_mesh *r = NULL;
    if (st == AU_OK) {
      st = au_io_read(out_path, &r, &msg);
      if (st != AU_OK || r->nv != m->nv || r->nf != m->nf) abort();
      for (long i = 0; i < 3L * m->nv; i++)
        if (!same_double(r->X[i], o.format != AU_IO_FORMAT_AUTO ? (double)(float)m->X[i] : m->X[i])) abort();
      if (memcmp(r->F, m->F, sizeof(int) * 3 * (size_t)m->nf) != 0) abort();
      au_mesh_free(&r);
    }
  }
  au_io_meta_free(&meta);
  if (meta) abort();
  au_mesh_free(&m);
  if (m) abort();
  return 0;
}
