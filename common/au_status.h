/* au_status.h - status codes and the message buffer shared by every authalic module. */
#ifndef AU_STATUS_H
#define AU_STATUS_H

#include <stddef.h>

#include "authalic.h"

#ifdef __cplusplus
extern "C" {
#endif

/* The status codes, au_msg and au_msg_set are public (include/authalic.h). */

#ifdef __cplusplus
}
#endif
#endif
