/* A program built against an installed libsfm, as robot code would be. */
#include <stdio.h>
#include <string.h>

#include <sfm/sfm.h>

int main(void)
{
    sfm_rng rng;
    if (sfm_rng_seed(&rng, 1) != SFM_OK)
        return 1;
    if (strcmp(sfm_status_str(SFM_E_WORKSPACE), "workspace too small") != 0)
        return 1;
    printf("consumer linked libsfm %d\n", sfm_version());
    return 0;
}
