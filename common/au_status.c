/* au_status.c - status strings and the message buffer. */
#include "au_status.h"

#include <stdarg.h>
#include <stdio.h>

const char *au_status_str(au_status s) {
  switch (s) {
#define AU_STATUS_STR(name, value, text) \
  case name:                             \
    return text;
    AU_STATUS_MAP(AU_STATUS_STR)
#undef AU_STATUS_STR
  }
  return "unknown status";
}

const char *au_status_name(au_status s) {
  switch (s) {
#define AU_STATUS_NAME(name, value, text) \
  case name:                              \
    return #name;
    AU_STATUS_MAP(AU_STATUS_NAME)
#undef AU_STATUS_NAME
  }
  return "AU_UNKNOWN";
}

int au_status_is_input_error(au_status s) { return (int)s <= -100; }

au_status au_msg_set(au_msg *m, au_status s, const char *fmt, ...) {
  if (m) {
    va_list ap;
    va_start(ap, fmt);
    vsnprintf(m->text, sizeof m->text, fmt, ap);
    va_end(ap);
  }
  return s;
}
