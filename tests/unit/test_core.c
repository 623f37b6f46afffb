#include <string.h>

#include "core/arena.h"
#include "sfm/sfm.h"
#include "sfm_test.h"

SFM_TEST(status_strings_are_distinct)
{
    const int codes[] = {SFM_OK, SFM_E_ARGUMENT, SFM_E_NONFINITE, SFM_E_WORKSPACE,
                         SFM_E_CAPACITY, SFM_E_SINGULAR, SFM_E_NO_CONVERGENCE, SFM_E_IO,
                         SFM_E_TIMEOUT, SFM_E_UNSUPPORTED, SFM_E_DEVICE_LOST,
                         SFM_E_NO_DEVICE, SFM_E_FORMAT};
    const int n = (int)(sizeof codes / sizeof codes[0]);
    for (int i = 0; i < n; i++) {
        SFM_CHECK(sfm_status_str(codes[i]) != NULL);
        for (int j = 0; j < i; j++)
            SFM_CHECK(strcmp(sfm_status_str(codes[i]), sfm_status_str(codes[j])) != 0);
    }
    SFM_CHECK(strcmp(sfm_status_str(-999), "unknown status") == 0);
    /* Pinned values are ABI. */
    SFM_CHECK_EQ_INT(SFM_E_ARGUMENT, -1);
    SFM_CHECK_EQ_INT(SFM_E_DEVICE_LOST, -10);
    SFM_CHECK_EQ_INT(SFM_E_FORMAT, -12);
}

SFM_TEST(arena_measure_matches_carve)
{
    static unsigned char buf[4096 + 64];
    for (int off = 0; off < 16; off++) {
        sfmi_arena m, a;
        sfmi_arena_measure(&m);
        (void)sfmi_arena_alloc(&m, 3);
        (void)SFM_ARENA_ARRAY(&m, double, 17);
        (void)sfmi_arena_alloc(&m, 1);
        size_t need = sfmi_arena_required(&m);
        SFM_CHECK(need > 0);
        /* exactly enough at any alignment of the caller's pointer */
        sfmi_arena_init(&a, buf + off, need);
        unsigned char *p1 = sfmi_arena_alloc(&a, 3);
        double *p2 = SFM_ARENA_ARRAY(&a, double, 17);
        unsigned char *p3 = sfmi_arena_alloc(&a, 1);
        SFM_CHECK(sfmi_arena_ok(&a));
        SFM_CHECK(p1 && p2 && p3);
        SFM_CHECK(((uintptr_t)p2 % SFM_WS_ALIGN) == 0);
        SFM_CHECK(p3 + 1 <= buf + off + need);
        /* one byte short fails at every alignment */
        sfmi_arena_init(&a, buf + off, need - 1);
        (void)sfmi_arena_alloc(&a, 3);
        (void)SFM_ARENA_ARRAY(&a, double, 17);
        (void)sfmi_arena_alloc(&a, 1);
        SFM_CHECK(!sfmi_arena_ok(&a));
    }
}

SFM_TEST(arena_too_small_is_sticky)
{
    static unsigned char buf[256];
    sfmi_arena a;
    sfmi_arena_init(&a, buf, 40);
    void *p = sfmi_arena_alloc(&a, 64);
    SFM_CHECK(p == NULL);
    SFM_CHECK(!sfmi_arena_ok(&a));
    SFM_CHECK(sfmi_arena_alloc(&a, 1) == NULL);
    sfmi_arena_init(&a, NULL, 100);
    SFM_CHECK(!sfmi_arena_ok(&a));
    sfmi_arena m;
    sfmi_arena_measure(&m);
    SFM_CHECK(!sfmi_arena_ok(&m));
    (void)sfmi_arena_alloc(&m, SIZE_MAX - 3);
    SFM_CHECK_EQ_INT(sfmi_arena_required(&m), 0);
}

SFM_TEST(rng_reference_sequence)
{
    /* splitmix64 from seed 0 gives these words (Vigna's reference
     * implementation); xoshiro256** first output from that state computed by
     * the reference formula below, independent of the library. */
    sfm_rng r;
    SFM_CHECK_EQ_INT(sfm_rng_seed(&r, 0), SFM_OK);
    SFM_CHECK(r.s[0] == 0xe220a8397b1dcdafULL);
    SFM_CHECK(r.s[1] == 0x6e789e6aa1b965f4ULL);
    SFM_CHECK(r.s[2] == 0x06c45d188009454fULL);
    SFM_CHECK(r.s[3] == 0xf88bb8a8724c81ecULL);
    uint64_t s1 = r.s[1] * 5;
    uint64_t expect = ((s1 << 7) | (s1 >> 57)) * 9;
    SFM_CHECK(sfm_rng_next(&r) == expect);
    SFM_CHECK_EQ_INT(sfm_rng_seed(NULL, 1), SFM_E_ARGUMENT);
}

SFM_TEST(rng_bounded_is_unbiased)
{
    sfm_rng r;
    sfm_rng_seed(&r, 42);
    enum { N = 7, DRAWS = 70000 };
    int hist[N] = {0};
    for (int i = 0; i < DRAWS; i++) {
        uint32_t k = sfm_rng_bounded(&r, N);
        SFM_CHECK(k < N);
        if (k < N)
            hist[k]++;
    }
    /* chi-square with 6 dof: 99.99th percentile is 27.9 */
    double chi = 0;
    for (int i = 0; i < N; i++) {
        double e = DRAWS / (double)N;
        chi += (hist[i] - e) * (hist[i] - e) / e;
    }
    SFM_CHECK_MSG(chi < 27.9, "chi2 = %g", chi);
    SFM_CHECK_EQ_INT(sfm_rng_bounded(&r, 0), 0);
    SFM_CHECK_EQ_INT(sfm_rng_bounded(&r, 1), 0);
}

SFM_TEST(rng_same_seed_same_stream)
{
    sfm_rng a, b;
    sfm_rng_seed(&a, 7);
    sfm_rng_seed(&b, 7);
    for (int i = 0; i < 1000; i++)
        SFM_CHECK(sfm_rng_next(&a) == sfm_rng_next(&b));
    double sum = 0, sum2 = 0;
    for (int i = 0; i < 20000; i++) {
        double x = sfm_rng_normal(&a);
        sum += x;
        sum2 += x * x;
    }
    SFM_CHECK_NEAR(sum / 20000, 0.0, 0.03);
    SFM_CHECK_NEAR(sum2 / 20000, 1.0, 0.04);
}
