/* libFuzzer target: mesh file bytes -> assembly -> static check (make fuzz). The first byte
 * picks the format by the file's ending (OBJ, OFF, PLY, STL), the rest is the file; it is written
 * beside an assembly file that names it, in a directory of this process's own. Headers that lie
 * about their counts must be refused before anything is allocated for them (libFuzzer's
 * -rss_limit_mb and -malloc_limit_mb catch an allocation that trusts one). */
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "cairn/cairn.h"
#include "fuzz.h"

static char dir[64];

static void remove_dir(void) {
    static const char *const kNames[] = {"m.obj", "m.off", "m.ply", "m.stl", "a.json"};
    char path[128];
    for (size_t i = 0; i < sizeof kNames / sizeof kNames[0]; i++) {
        snprintf(path, sizeof path, "%s/%s", dir, kNames[i]);
        unlink(path);
    }
    rmdir(dir);
}

static bool write_file(const char *path, const void *data, size_t size) {
    FILE *f = fopen(path, "wb");
    if (!f) return false;
    bool ok = fwrite(data, 1, size, f) == size;
    return fclose(f) == 0 && ok;
}

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size) {
    static const char *const kExt[] = {"obj", "off", "ply", "stl"};
    if (!dir[0]) {
        snprintf(dir, sizeof dir, "/tmp/cairn_fuzz_mesh.XXXXXX");
        if (!mkdtemp(dir)) abort();
        atexit(remove_dir);
    }
    if (size < 1) return 0;
    const char *ext = kExt[data[0] % 4];
    char mesh[128], json[128], text[512];
    snprintf(mesh, sizeof mesh, "%s/m.%s", dir, ext);
    snprintf(json, sizeof json, "%s/a.json", dir);
    snprintf(text, sizeof text,
             "{\"dimension\": 3, \"parts\": [{\"name\": \"t\", \"fixed\": true, \"box\": "
             "{\"min\": [-50, -50, -1], \"max\": [50, 50, 0]}}, {\"name\": \"m\", \"mesh\": \"m.%s\"}]}",
             ext);
    if (!write_file(mesh, data + 1, size - 1) || !write_file(json, text, strlen(text))) abort();
    cnAssembly *a = NULL;
    cnDiag d;
    if (cn_assembly_load_file(json, &a, &d) == CN_OK) {
        cnCheckResult r;
        cnCheckOptions o = cn_check_options_default();
        o.max_nodes = 20;
        if (cn_check(a, &o, &r, &d) == CN_OK) cn_check_result_free(&r);
        cn_assembly_free(a);
    }
    return 0;
}
