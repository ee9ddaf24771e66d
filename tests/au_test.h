/* au_test.h - minimal test harness: named cases, assertions that print both operands and file:line
 * and never compile out. Each test executable runs one case named on its command line. */
#ifndef AU_TEST_H
#define AU_TEST_H

#include <math.h>
#include <stdio.h>

typedef struct au_test_case {
  const char *name;
  int (*fn)(void); /* 0 pass, 1 fail, 77 skip */
} au_test_case;

/* Run the case named argv[1] (or all cases without an argument). Returns the exit status. */
int au_test_main(int argc, char **argv, const au_test_case *cases, int ncases);

/* Path of a shared mesh (../shared/meshes/NAME) into buf; returns 0 if the file is missing. */
int au_test_shared_mesh(const char *name, char *buf, size_t len);

/* The project's own mesh data/NAME.obj, read (the caller frees it with au_mesh_free); NULL, with the
 * reader's message on stderr, when it cannot be read. */
struct au_mesh *au_test_data_mesh(const char *name);

#define AU_SKIP 77

/* The text of an optional message buffer (so macros can take &msg or NULL without warnings). */
static inline const char *au_test_msg_text(const void *m) { return m ? (const char *)m : ""; }

#define AU_CHECK(cond)                                                   \
  do {                                                                   \
    if (!(cond)) {                                                       \
      fprintf(stderr, "%s:%d: check failed: %s\n", __FILE__, __LINE__, #cond); \
      return 1;                                                          \
    }                                                                    \
  } while (0)

#define AU_CHECK_INT(a, op, b)                                                             \
  do {                                                                                     \
    long long au_a_ = (long long)(a), au_b_ = (long long)(b);                              \
    if (!(au_a_ op au_b_)) {                                                               \
      fprintf(stderr, "%s:%d: check failed: %s %s %s (%lld vs %lld)\n", __FILE__, __LINE__, \
              #a, #op, #b, au_a_, au_b_);                                                  \
      return 1;                                                                            \
    }                                                                                      \
  } while (0)

#define AU_CHECK_DBL(a, op, b)                                                               \
  do {                                                                                       \
    double au_a_ = (double)(a), au_b_ = (double)(b);                                         \
    if (!(au_a_ op au_b_)) {                                                                 \
      fprintf(stderr, "%s:%d: check failed: %s %s %s (%.17g vs %.17g)\n", __FILE__, __LINE__, \
              #a, #op, #b, au_a_, au_b_);                                                    \
      return 1;                                                                              \
    }                                                                                        \
  } while (0)

#define AU_CHECK_NEAR(a, b, tol)                                                                  \
  do {                                                                                            \
    double au_a_ = (double)(a), au_b_ = (double)(b), au_t_ = (double)(tol);                       \
    if (!(fabs(au_a_ - au_b_) <= au_t_)) {                                                        \
      fprintf(stderr, "%s:%d: check failed: |%s - %s| <= %s (%.17g vs %.17g, diff %.3g)\n",       \
              __FILE__, __LINE__, #a, #b, #tol, au_a_, au_b_, fabs(au_a_ - au_b_));               \
      return 1;                                                                                   \
    }                                                                                             \
  } while (0)

/* Check a status; print its name and the message on failure. */
#define AU_CHECK_STATUS(expr, want, msgp)                                                         \
  do {                                                                                            \
    au_status au_s_ = (expr);                                                                     \
    if (au_s_ != (want)) {                                                                        \
      fprintf(stderr, "%s:%d: %s returned %s, want %s (%s)\n", __FILE__, __LINE__, #expr,          \
              au_status_name(au_s_), au_status_name(want), au_test_msg_text(msgp));           \
      return 1;                                                                                   \
    }                                                                                             \
  } while (0)

#endif
