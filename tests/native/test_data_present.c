#include <stdio.h>

#include "sfm_test.h"

/* Real-data tests read ../shared/data; a fresh clone without it says so in
 * one clear line instead of passing silently. */
SFM_TEST(shared_data_available)
{
    (void)t;
    FILE *f = fopen("../shared/data/README.md", "r");
    if (f == NULL) {
        printf("SKIP: ../shared/data not found; real-data tests will be skipped\n");
        return;
    }
    fclose(f);
}
