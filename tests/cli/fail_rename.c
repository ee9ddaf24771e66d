/* fail_rename.c - a preload library for tests/cli/rename_fault.sh: the N-th call of rename() fails with
 * EIO (N from the environment variable AU_FAIL_RENAME), every other call is the C library's. It lets a
 * test reach the program's paths for an output that cannot be put into place, which no file system
 * state reaches reliably. */
#define _GNU_SOURCE
#include <dlfcn.h>
#include <errno.h>
#include <stdio.h>
#include <stdlib.h>

int rename(const char *from, const char *to) {
  static int calls;
  static int (*real)(const char *, const char *);
  if (!real) real = (int (*)(const char *, const char *))dlsym(RTLD_NEXT, "rename");
  const char *n = getenv("AU_FAIL_RENAME");
  if (n && atoi(n) == ++calls) {
    errno = EIO;
    return -1;
  }
  return real ? real(from, to) : (errno = ENOSYS, -1);
}
