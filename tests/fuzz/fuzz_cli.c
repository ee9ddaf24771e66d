/* fuzz_cli.c - libFuzzer harness for the argument parsing of the `authalic` program.
 *
 * The bytes are split at NUL bytes into at most 24 arguments after "authalic", and the program's
 * main (tools/authalic.c, compiled with -Dmain=au_cli_main) runs on them. Runs happen in a private
 * scratch folder that holds a few small meshes (a.obj: an octahedron, b.off: a tetrahedron with
 * a boundary, t.obj: a torus), so that valid command lines reach the commands and really map and
 * write; an argument containing '/' is refused, so that nothing outside the folder can be read or
 * written, and every file a run creates is removed after it. stdout and stderr are swapped for
 * /dev/null during a run (the sanitizers write to file descriptor 2 directly and stay visible).
 * Checked: no crash, leak or undefined behaviour; the exit code is 0, 1 or 2; and a run that did
 * not exit 0 left no file behind. */
#define _POSIX_C_SOURCE 200809L

#include <dirent.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

int au_cli_main(int argc, char **argv);

#define MAX_ARGS 24

static char dir[64];
static FILE *devnull;
static const char *const seeds[] = {"a.obj", "b.off", "t.obj"};

static void put(const char *name, const char *text) {
  FILE *fp = fopen(name, "w");
  if (!fp || fputs(text, fp) < 0 || fclose(fp) != 0) abort();
}

static int is_seed(const char *name) {
  for (size_t i = 0; i < sizeof seeds / sizeof seeds[0]; i++)
    if (strcmp(name, seeds[i]) == 0) return 1;
  return 0;
}

/* Remove everything but the seed meshes; returns how many files were removed. */
static int sweep(void) {
  DIR *d = opendir(".");
  if (!d) abort();
  int n = 0;
  struct dirent *e;
  while ((e = readdir(d)) != NULL) {
    if (!strcmp(e->d_name, ".") || !strcmp(e->d_name, "..") || is_seed(e->d_name)) continue;
    if (unlink(e->d_name) != 0 && rmdir(e->d_name) != 0) abort();
    n++;
  }
  closedir(d);
  return n;
}

static void cleanup(void) {
  if (chdir(dir) == 0) {
    sweep();
    for (size_t i = 0; i < sizeof seeds / sizeof seeds[0]; i++) unlink(seeds[i]);
    if (chdir("/") == 0) rmdir(dir);
  }
}

int LLVMFuzzerInitialize(int *argc, char ***argv) {
  (void)argc, (void)argv;
  snprintf(dir, sizeof dir, "%s/au_fuzz_cli.XXXXXX", access("/dev/shm", W_OK) == 0 ? "/dev/shm" : "/tmp");
  if (!mkdtemp(dir) || chdir(dir) != 0) abort();
  put("a.obj", "v 1 0 0\nv 0 1 0\nv -1 0 0\nv 0 -1 0\nv 0 0 1\nv 0 0 -1\n"
               "f 1 2 5\nf 2 3 5\nf 3 4 5\nf 4 1 5\nf 2 1 6\nf 3 2 6\nf 4 3 6\nf 1 4 6\n");
  put("b.off", "OFF\n4 3 0\n0 0 0\n1 0 0\n0 1 0\n0 0 1\n3 0 1 3\n3 0 3 2\n3 1 2 3\n");
  /* a 4 x 3 torus */
  char buf[4096];
  size_t n = 0;
  for (int i = 0; i < 4; i++)
    for (int j = 0; j < 3; j++) {
      static const double c[4] = {1, 0, -1, 0}, s[4] = {0, 1, 0, -1}, cj[3] = {1, -0.5, -0.5}, sj[3] = {0, 0.866, -0.866};
      n += (size_t)snprintf(buf + n, sizeof buf - n, "v %g %g %g\n", (2 + 0.7 * cj[j]) * c[i], (2 + 0.7 * cj[j]) * s[i],
                            0.7 * sj[j]);
    }
  for (int i = 0; i < 4; i++)
    for (int j = 0; j < 3; j++) {
      int a = 3 * i + j + 1, b = 3 * ((i + 1) % 4) + j + 1, c = 3 * ((i + 1) % 4) + (j + 1) % 3 + 1,
          d = 3 * i + (j + 1) % 3 + 1;
      n += (size_t)snprintf(buf + n, sizeof buf - n, "f %d %d %d\nf %d %d %d\n", a, b, c, a, c, d);
    }
  put("t.obj", buf);
  devnull = fopen("/dev/null", "w");
  if (!devnull) abort();
  atexit(cleanup);
  return 0;
}

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size) {
  if (size > 4096) return 0;
  char *copy = malloc(size + 1);
  if (!copy) abort();
  memcpy(copy, data, size);
  copy[size] = '\0';
  char *argv[MAX_ARGS + 2];
  int argc = 0;
  argv[argc++] = "authalic";
  for (char *p = copy; p <= copy + size && argc <= MAX_ARGS;) {
    size_t len = strlen(p);
    if (memchr(p, '/', len)) { /* sandbox: no path outside the scratch folder */
      free(copy);
      return 0;
    }
    argv[argc++] = p;
    p += len + 1;
  }
  argv[argc] = NULL;

  FILE *out = stdout, *err = stderr;
  stdout = devnull;
  stderr = devnull;
  int rc = au_cli_main(argc, argv);
  stdout = out;
  stderr = err;
  free(copy);
  int left = sweep();
  if (rc != 0 && rc != 1 && rc != 2) abort();
  if (rc != 0 && left > 0) abort(); /* a failed run must not leave a file */
  return 0;
}
