/* The library's version, for programs that check what they run against. */
#include "cairn/cairn.h"

const char *cn_version(void) { return CAIRN_VERSION; }
