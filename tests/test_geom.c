#include "test.h"
void test_geom(void) {}
