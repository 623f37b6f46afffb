#include "sfm_test.h"

#include <stdarg.h>
#include <string.h>

#include "sfm/sfm_rotation.h"

void sfm_test_fail(sfm_test_ctx *t, const char *file, int line, const char *fmt, ...)
{
    va_list ap;
    t->failures++;
    if (t->failures > 20)
        return; /* keep logs readable when a loop fails every time */
    printf("  FAIL %s (%s:%d): ", t->name, file, line);
    va_start(ap, fmt);
    vprintf(fmt, ap);
    va_end(ap);
    printf("\n");
}

double sfm_test_uniform(sfm_test_ctx *t, double lo, double hi)
{
    return lo + (hi - lo) * sfm_rng_uniform(&t->rng);
}

double sfm_test_normal(sfm_test_ctx *t, double sigma)
{
    return sigma * sfm_rng_normal(&t->rng);
}

void sfm_test_random_unit(sfm_test_ctx *t, double v[3])
{
    double n;
    do {
        for (int i = 0; i < 3; i++)
            v[i] = sfm_rng_normal(&t->rng);
        n = sqrt(v[0] * v[0] + v[1] * v[1] + v[2] * v[2]);
    } while (n < 1e-6);
    for (int i = 0; i < 3; i++)
        v[i] /= n;
}

void sfm_test_random_rotation(sfm_test_ctx *t, double R[9])
{
    double q[4], n;
    do {
        for (int i = 0; i < 4; i++)
            q[i] = sfm_rng_normal(&t->rng);
        n = sqrt(q[0] * q[0] + q[1] * q[1] + q[2] * q[2] + q[3] * q[3]);
    } while (n < 1e-6);
    /* Quaternion to matrix written out here so the harness does not depend on
     * the code under test. */
    double w = q[0] / n, x = q[1] / n, y = q[2] / n, z = q[3] / n;
    R[0] = 1 - 2 * (y * y + z * z); R[1] = 2 * (x * y - w * z);     R[2] = 2 * (x * z + w * y);
    R[3] = 2 * (x * y + w * z);     R[4] = 1 - 2 * (x * x + z * z); R[5] = 2 * (y * z - w * x);
    R[6] = 2 * (x * z - w * y);     R[7] = 2 * (y * z + w * x);     R[8] = 1 - 2 * (x * x + y * y);
}

void sfm_test_fill_canary(void *buf, size_t n)
{
    memset(buf, 0xA5, n);
}

int sfm_test_canary_intact(const void *buf, size_t n)
{
    const unsigned char *p = (const unsigned char *)buf;
    for (size_t i = 0; i < n; i++)
        if (p[i] != 0xA5)
            return 0;
    return 1;
}
