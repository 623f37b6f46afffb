/* Fuzz target: sfm_selfcal_solve. A fixed scene (5 views of f = 500 px
 * turning about two axes around 14 points, exact projections, in a
 * projective frame) is edited by the input: each 10-byte record sets one
 * entry of P, X, the image sizes or the observations' pixels to a value
 * (special values, or 8 raw bytes), rescales a camera, moves an
 * observation's view or point index, drops observations, changes a count
 * or an option, or shortens the workspace. Any input gives a status the
 * header lists; nothing is written on an argument, non-finite or
 * workspace status, only the report on SFM_E_SINGULAR or
 * SFM_E_NO_CONVERGENCE, and on SFM_OK finite outputs (K, H, poses,
 * points) with every focal length positive. The workspace is an
 * exact-size heap block (ASan sees a write past it). */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "sfm/sfm_selfcal.h"

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size);

enum { M = 5, N = 14, NO = M * N };

static double P[12 * M], X[4 * N], wh[2 * M], xy[2 * NO];
static int oc[NO], op[NO];

static void scene(void)
{
    /* a projective frame: P_i = K [R_i | t_i] G, X_j = G^{-1} (X_j, 1);
     * G = [I 0; g^T 1] (g = (0.1, -0.05, 0.02)), G^{-1} = [I 0; -g^T 1] */
    const double g[3] = {0.1, -0.05, 0.02}, f = 500, cx = 319.5, cy = 239.5;
    for (int j = 0; j < N; j++) {
        const double Xw[3] = {-1.5 + 3.0 * (j % 5) / 4, -1.0 + 2.0 * ((j / 5) % 3) / 2 + 0.1 * j, 6.0 + (j % 3)};
        for (int r = 0; r < 3; r++)
            X[4 * j + r] = Xw[r];
        X[4 * j + 3] = 1 - (g[0] * Xw[0] + g[1] * Xw[1] + g[2] * Xw[2]);
    }
    for (int i = 0; i < M; i++) {
        const double a = 0.12 * i, b = 0.07 * i * (i % 2 ? -1 : 1);
        const double ca = cos(a), sa = sin(a), cb = cos(b), sb = sin(b);
        /* R = Ry(a) Rx(b); centre C = (0.6 i, 0.2 (i % 2), 0.1 i) */
        const double R[9] = {ca, sa * sb, sa * cb, 0, cb, -sb, -sa, ca * sb, ca * cb};
        const double C[3] = {0.6 * i, 0.2 * (i % 2), 0.1 * i};
        double Rt[12];
        for (int r = 0; r < 3; r++) {
            for (int c = 0; c < 3; c++)
                Rt[4 * r + c] = R[3 * r + c];
            Rt[4 * r + 3] = -(R[3 * r] * C[0] + R[3 * r + 1] * C[1] + R[3 * r + 2] * C[2]);
        }
        const double K[9] = {f, 0, cx, 0, f, cy, 0, 0, 1};
        double Pm[12];
        for (int r = 0; r < 3; r++)
            for (int c = 0; c < 4; c++)
                Pm[4 * r + c] = K[3 * r] * Rt[c] + K[3 * r + 1] * Rt[4 + c] + K[3 * r + 2] * Rt[8 + c];
        /* P = Pm G: columns 0..2 gain g * column 3 */
        for (int r = 0; r < 3; r++) {
            for (int c = 0; c < 3; c++)
                P[12 * i + 4 * r + c] = Pm[4 * r + c] + Pm[4 * r + 3] * g[c];
            P[12 * i + 4 * r + 3] = Pm[4 * r + 3];
        }
        wh[2 * i] = 640, wh[2 * i + 1] = 480;
    }
    for (int i = 0, k = 0; i < M; i++)
        for (int j = 0; j < N; j++, k++) {
            double y[3];
            for (int r = 0; r < 3; r++)
                y[r] = P[12 * i + 4 * r] * X[4 * j] + P[12 * i + 4 * r + 1] * X[4 * j + 1] +
                       P[12 * i + 4 * r + 2] * X[4 * j + 2] + P[12 * i + 4 * r + 3] * X[4 * j + 3];
            oc[k] = i, op[k] = j;
            xy[2 * k] = y[0] / y[2];
            xy[2 * k + 1] = y[1] / y[2];
        }
}

/* 8 bytes: a special value when the first is below 64, else the raw double */
static double value(const uint8_t *b)
{
    static const double special[8] = {0.0, -0.0, 1.0, -1.0, 1e300, -1e-300, HUGE_VAL, 0.0};
    if (b[0] < 64)
        return b[0] == 7 ? nan("") : special[b[0] % 8];
    double v;
    memcpy(&v, b, sizeof v);
    return v;
}

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    static int once;
    if (!once)
        scene(), once = 1;
    double Pf[12 * M], Xf[4 * N], whf[2 * M], xyf[2 * NO];
    int ocf[NO], opf[NO];
    memcpy(Pf, P, sizeof P), memcpy(Xf, X, sizeof X), memcpy(whf, wh, sizeof wh), memcpy(xyf, xy, sizeof xy);
    memcpy(ocf, oc, sizeof oc), memcpy(opf, op, sizeof op);
    int m = M, n = N, no = NO;
    size_t short_by = 0;
    sfm_selfcal_options o;
    sfm_selfcal_default_options(&o);
    o.sweep_steps = 5; /* fast: the fuzzer wants many runs */
    const sfm_selfcal_options *po = &o;
    for (size_t at = 0; at + 10 <= size && at < 160; at += 10) {
        const uint8_t *rec = data + at;
        const unsigned idx = rec[1];
        const double v = value(rec + 2);
        switch (rec[0] % 13) {
        case 0: Pf[idx % (12 * M)] = v; break;
        case 1: Xf[idx % (4 * N)] = v; break;
        case 2: whf[idx % (2 * M)] = v; break;
        case 3: xyf[idx % (2 * NO)] = v; break;
        case 4: ocf[idx % NO] = (int)rec[2] - 2; break;                     /* -2 .. 253 */
        case 5: opf[idx % NO] = (int)rec[2] - 2; break;
        case 6: no = (int)(idx % (NO + 1)) - (rec[2] == 0); break;          /* -1 .. NO */
        case 7: m = (int)(idx % (M + 1)); break;                            /* 0 .. M */
        case 8: n = (int)(idx % (N + 1)); break;
        case 9: short_by = rec[2] == 0 ? 1 : (size_t)rec[2] * 8; break;
        case 10:
            switch (idx % 8) {
            case 0: o.sweep = (int)rec[2] - 1; break;
            case 1: o.sweep_steps = (int)rec[2]; break;
            case 2: o.focal_min = v; break;
            case 3: o.focal_max = v; break;
            case 4: o.per_view_focal = rec[2] % 3; break;
            case 5: o.principal = (int)(rec[2] % 4) - (rec[2] > 250); break;
            case 6: o.loss_scale = v; break;
            default: o.max_rms = v; break;
            }
            break;
        case 12: /* a whole camera rescaled: the same camera */
            for (int k = 0; k < 12; k++)
                Pf[12 * (idx % M) + k] *= v;
            break;
        default:
            if (idx % 4 == 0)
                po = NULL;
            else if (idx % 4 == 1)
                o.min_front = v;
            else if (idx % 4 == 2)
                o.max_iterations = (int)rec[2] - 1;
            else
                o.min_profile = v;
            break;
        }
    }
    size_t need = sfm_selfcal_workspace_size(m, n, no);
    size_t ws_size = need > short_by ? need - short_by : 0;
    void *ws = malloc(ws_size ? ws_size : 1);
    if (ws == NULL)
        return 0;
    static double K[9 * M], H[16], Xm[3 * N];
    static sfm_pose poses[M];
    static sfm_selfcal_report rep;
    static double K0[9 * M], H0[16], Xm0[3 * N];
    static sfm_pose poses0[M];
    static sfm_selfcal_report rep0;
    memset(K, 0xA5, sizeof K), memset(H, 0xA5, sizeof H), memset(Xm, 0xA5, sizeof Xm);
    memset(poses, 0xA5, sizeof poses), memset(&rep, 0xA5, sizeof rep);
    memcpy(K0, K, sizeof K), memcpy(H0, H, sizeof H), memcpy(Xm0, Xm, sizeof Xm);
    memcpy(poses0, poses, sizeof poses), memcpy(&rep0, &rep, sizeof rep);
    const int st = sfm_selfcal_solve(m, Pf, whf, n, Xf, no, ocf, opf, xyf, po, K, H, poses, Xm, &rep,
                                     ws_size ? ws : NULL, ws_size);
    const int outs = memcmp(K, K0, sizeof K) == 0 && memcmp(H, H0, sizeof H) == 0 &&
                     memcmp(Xm, Xm0, sizeof Xm) == 0 && memcmp(poses, poses0, sizeof poses) == 0;
    const int rep_kept = memcmp(&rep, &rep0, sizeof rep) == 0;
    if (st == SFM_OK) {
        if (outs || rep_kept)
            abort();
        for (int i = 0; i < m; i++)
            if (!(K[9 * i] > 0) || !isfinite(K[9 * i]) || !isfinite(K[9 * i + 2]) || !isfinite(K[9 * i + 5]))
                abort();
        for (int k = 0; k < 16; k++)
            if (!isfinite(H[k]))
                abort();
        for (int i = 0; i < m; i++)
            for (int k = 0; k < 9; k++)
                if (!isfinite(poses[i].R[k]) || (k < 3 && !isfinite(poses[i].t[k])))
                    abort();
        for (int k = 0; k < 3 * n; k++)
            if (!isfinite(Xm[k]))
                abort();
    } else if (st == SFM_E_SINGULAR || st == SFM_E_NO_CONVERGENCE) {
        if (!outs || rep_kept)
            abort();
    } else if (st == SFM_E_ARGUMENT || st == SFM_E_NONFINITE || st == SFM_E_WORKSPACE) {
        if (!outs || !rep_kept)
            abort();
    } else {
        abort();
    }
    free(ws);
    return 0;
}
