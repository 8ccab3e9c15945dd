#include "test.h"
void test_stability(void) {}
