#include "test.h"
void test_contact(void) {}
