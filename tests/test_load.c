#include "test.h"
void test_load(void) {}
