/*
 * sfm_trifocal_7pt for callgrind: `trifocal_callgrind CALLS [N]` solves CALLS
 * problems (cycling over 100 synthetic scenes of N triplets, default 7, 0.5 px
 * noise). bench/trifocal_callgrind.sh runs it at two call counts and prints
 * the difference per call, so scene generation and start-up cancel.
 */
#include <stdio.h>
#include <stdlib.h>

#include "sfm/sfm.h"
#include "trifocal_scene.h"

enum { SCENES = 100, NMAX = 100 };


int main(int argc, char **argv)
{
    static double y[3][SCENES][2 * NMAX];
    int calls = argc > 1 ? atoi(argv[1]) : 100;
    int n = argc > 2 ? atoi(argv[2]) : 7;
    if (calls < 0 || n < 7 || n > NMAX) {
        fprintf(stderr, "usage: trifocal_callgrind CALLS [N in 7..%d]\n", NMAX);
        return 2;
    }
    sfm_rng r;
    sfm_rng_seed(&r, 7);
    for (int p = 0; p < SCENES; p++) {
        double P[3][12];
        for (int v = 0; v < 3; v++)
            camera(&r, P[v]);
        for (int i = 0; i < n; i++) {
            double X[3] = {6 * sfm_rng_uniform(&r) - 3, 4 * sfm_rng_uniform(&r) - 2, 5 + 5 * sfm_rng_uniform(&r)};
            for (int v = 0; v < 3; v++) {
                (void)project(P[v], X, &y[v][p][2 * i]); /* depths 5..10: in front */
                for (int k = 0; k < 2; k++)
                    y[v][p][2 * i + k] += 0.5 * sfm_rng_normal(&r);
            }
        }
    }
    size_t ws = sfm_trifocal_7pt_workspace_size();
    void *w = malloc(ws);
    double T[27], acc = 0;
    int ok = 0;
    for (int c = 0; c < calls; c++) {
        int p = c % SCENES;
        if (sfm_trifocal_7pt(y[0][p], y[1][p], y[2][p], n, T, w, ws) == SFM_OK) {
            acc += T[0];
            ok++;
        }
    }
    printf("%d of %d solved (checksum %.6f)\n", ok, calls, acc);
    free(w);
    return 0;
}
