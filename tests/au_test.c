/* au_test.c - the test harness's runner. */
#include "au_test.h"

#include "authalic.h"

#include <string.h>
#include <sys/stat.h>

int au_test_main(int argc, char **argv, const au_test_case *cases, int ncases) {
  int failed = 0, ran = 0;
  for (int i = 0; i < ncases; i++) {
    if (argc > 1 && strcmp(argv[1], cases[i].name) != 0) continue;
    int r = cases[i].fn();
    ran++;
    if (argc > 1) return r;
    printf("%-40s %s\n", cases[i].name, r == 0 ? "ok" : r == AU_SKIP ? "skipped" : "FAILED");
    if (r != 0 && r != AU_SKIP) failed++;
  }
  if (ran == 0) {
    fprintf(stderr, "no test case named '%s'\n", argc > 1 ? argv[1] : "");
    return 2;
  }
  return failed ? 1 : 0;
}

int au_test_shared_mesh(const char *name, char *buf, size_t len) {
  struct stat st;
  snprintf(buf, len, "%s/meshes/%s", AU_SHARED_DIR, name);
  return stat(buf, &st) == 0 && S_ISREG(st.st_mode);
}

struct au_mesh *au_test_data_mesh(const char *name) {
  char path[4096];
  snprintf(path, sizeof path, "%s/data/%s.obj", AU_SOURCE_DIR, name);
  au_mesh *m = NULL;
  au_msg msg = {0};
  if (au_mesh_read(path, &m, &msg) != AU_OK) fprintf(stderr, "%s: %s\n", path, msg.text);
  return m;
}
