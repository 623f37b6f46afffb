/* Helpers shared by the capture tests (host only: files, temp directories). */
#ifndef CAP_TEST_H
#define CAP_TEST_H

#include <stddef.h>
#include <stdint.h>

#include "sfm/sfm_capture.h"

/* Calls to malloc/calloc/realloc made through the linker's --wrap (every
 * object of the test program, libsfm_capture.a included). */
extern unsigned long cap_alloc_calls;

/* A fresh empty directory under $SFM_TEST_TMP (else /tmp); path in out. */
int cap_tmpdir(char *out, size_t cap);
/* Removes a directory tree made by a test (one level of subdirectories). */
void cap_rmtree(const char *dir);
/* Writes bytes to dir/name. */
int cap_write_file(const char *dir, const char *name, const void *data, size_t n);
/* Reads a file into buf; returns the length or -1. */
long cap_read_file(const char *path, void *buf, size_t cap);
/* A deterministic synthetic gray frame k: a moving gradient plus texture. */
void cap_synth_frame(uint8_t *img, int w, int h, int stride, int k);

#endif
