/* The entry point every fuzz target defines: libFuzzer calls it (make fuzz), and so does
 * replay_main.c, which replays the seed corpus and every past finding under `make test`. */
#ifndef CAIRN_FUZZ_H
#define CAIRN_FUZZ_H
#include <stddef.h>
#include <stdint.h>
int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size);
#endif
