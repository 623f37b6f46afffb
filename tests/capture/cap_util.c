#define _DEFAULT_SOURCE
#include <dirent.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

#include "cap_test.h"

unsigned long cap_alloc_calls;

void *__real_malloc(size_t n);
void *__real_calloc(size_t a, size_t b);
void *__real_realloc(void *p, size_t n);
void __real_free(void *p);
void *__wrap_malloc(size_t n);
void *__wrap_calloc(size_t a, size_t b);
void *__wrap_realloc(void *p, size_t n);
void __wrap_free(void *p);

void *__wrap_malloc(size_t n)
{
    cap_alloc_calls++;
    return __real_malloc(n);
}
void *__wrap_calloc(size_t a, size_t b)
{
    cap_alloc_calls++;
    return __real_calloc(a, b);
}
void *__wrap_realloc(void *p, size_t n)
{
    cap_alloc_calls++;
    return __real_realloc(p, n);
}
void __wrap_free(void *p) { __real_free(p); }

int cap_tmpdir(char *out, size_t cap)
{
    const char *base = getenv("SFM_TEST_TMP");
    if (base == NULL || base[0] == '\0')
        base = "/tmp";
    mkdir(base, 0755);
    int n = snprintf(out, cap, "%s/sfmcap-XXXXXX", base);
    if (n < 0 || (size_t)n >= cap)
        return -1;
    return mkdtemp(out) ? 0 : -1;
}

static void rm_level(const char *dir, int depth)
{
    DIR *d = opendir(dir);
    if (d == NULL)
        return;
    struct dirent *e;
    char path[1200];
    while ((e = readdir(d)) != NULL) {
        if (strcmp(e->d_name, ".") == 0 || strcmp(e->d_name, "..") == 0)
            continue;
        snprintf(path, sizeof path, "%s/%s", dir, e->d_name);
        struct stat st;
        if (lstat(path, &st) == 0 && S_ISDIR(st.st_mode)) {
            if (depth < 2)
                rm_level(path, depth + 1);
        } else {
            unlink(path);
        }
    }
    closedir(d);
    rmdir(dir);
}

void cap_rmtree(const char *dir) { rm_level(dir, 0); }

int cap_write_file(const char *dir, const char *name, const void *data, size_t n)
{
    char path[1200];
    snprintf(path, sizeof path, "%s/%s", dir, name);
    FILE *f = fopen(path, "wb");
    if (f == NULL)
        return -1;
    size_t k = fwrite(data, 1, n, f);
    return (fclose(f) == 0 && k == n) ? 0 : -1;
}

long cap_read_file(const char *path, void *buf, size_t cap)
{
    FILE *f = fopen(path, "rb");
    if (f == NULL)
        return -1;
    size_t n = fread(buf, 1, cap, f);
    fclose(f);
    return (long)n;
}

void cap_synth_frame(uint8_t *img, int w, int h, int stride, int k)
{
    for (int y = 0; y < h; y++)
        for (int x = 0; x < w; x++) {
            unsigned v = (unsigned)(x * 3 + y * 2 + k * 7) + (unsigned)(((x / 4) ^ (y / 4)) & 1) * 40u;
            img[(size_t)y * (size_t)stride + (size_t)x] = (uint8_t)(v & 255u);
        }
}
