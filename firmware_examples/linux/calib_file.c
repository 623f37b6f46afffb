/* Camera calibration files (see calib_file.h): the file is flattened into
 * (dotted key, value text) entries, "camera_matrix.data" or
 * "cam1.intrinsics", then each format reads the keys it defines. */
#define _POSIX_C_SOURCE 200809L
#include "calib_file.h"

#include <ctype.h>
#include <math.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

enum { CF_MAX_ENTRIES = 256, CF_KEY = 96, CF_VAL = 4096, CF_MAX_FILE = 1 << 20, CF_DEPTH = 8 };

typedef struct cf_entry {
    char key[CF_KEY];
    char val[CF_VAL];
} cf_entry;

typedef struct cf_doc {
    cf_entry *e;
    int n;
    const char *path;
    char *err;
    size_t err_size;
} cf_doc;

static int fail(cf_doc *d, int status, const char *field, const char *fmt, ...)
{
    if (d->err != NULL && d->err_size > 0) {
        char msg[512];
        va_list ap;
        va_start(ap, fmt);
        vsnprintf(msg, sizeof msg, fmt, ap);
        va_end(ap);
        if (field != NULL)
            snprintf(d->err, d->err_size, "%s: field '%s': %s", d->path, field, msg);
        else
            snprintf(d->err, d->err_size, "%s: %s", d->path, msg);
    }
    return status;
}

static int add(cf_doc *d, const char *key, const char *val, size_t val_len)
{
    if (d->n == CF_MAX_ENTRIES)
        return fail(d, SFM_E_CAPACITY, NULL, "more than %d entries", CF_MAX_ENTRIES);
    if (strlen(key) >= CF_KEY || val_len >= CF_VAL)
        return fail(d, SFM_E_CAPACITY, key, "key or value too long");
    cf_entry *e = &d->e[d->n++];
    strcpy(e->key, key);
    memcpy(e->val, val, val_len);
    e->val[val_len] = '\0';
    return SFM_OK;
}

static const char *get(const cf_doc *d, const char *key)
{
    for (int i = 0; i < d->n; i++)
        if (strcmp(d->e[i].key, key) == 0)
            return d->e[i].val;
    return NULL;
}

static char *trim(char *s)
{
    while (isspace((unsigned char)*s))
        s++;
    size_t n = strlen(s);
    while (n > 0 && isspace((unsigned char)s[n - 1]))
        s[--n] = '\0';
    return s;
}

/* ---- YAML (the block style OpenCV, ROS, Kalibr and EuRoC write) --------- */

static void strip_comment(char *s)
{
    int quote = 0;
    for (char *p = s; *p; p++) {
        if (*p == '"' || *p == '\'')
            quote = !quote;
        else if (*p == '#' && !quote && (p == s || isspace((unsigned char)p[-1]))) {
            *p = '\0';
            return;
        }
    }
}

static int parse_yaml(cf_doc *d, char *text)
{
    char keys[CF_DEPTH][CF_KEY];
    int indents[CF_DEPTH], depth = 0, lineno = 0;
    char *save = NULL;
    char pending_key[CF_KEY * 2] = "", pending[CF_VAL];
    size_t pending_len = 0;
    for (char *line = strtok_r(text, "\n", &save); line; line = strtok_r(NULL, "\n", &save)) {
        lineno++;
        strip_comment(line);
        if (pending_key[0]) { /* a flow list spanning lines */
            char *t = trim(line);
            size_t k = strlen(t);
            if (pending_len + k + 2 >= sizeof pending)
                return fail(d, SFM_E_CAPACITY, pending_key, "value too long");
            pending[pending_len++] = ' ';
            memcpy(pending + pending_len, t, k);
            pending_len += k;
            if (strchr(t, ']')) {
                int st = add(d, pending_key, pending, pending_len);
                if (st < 0)
                    return st;
                pending_key[0] = '\0';
            }
            continue;
        }
        int indent = 0;
        while (line[indent] == ' ')
            indent++;
        char *s = trim(line);
        if (*s == '\0' || strncmp(s, "%YAML", 5) == 0 || strcmp(s, "---") == 0 || *s == '-' ||
            strcmp(s, "...") == 0)
            continue; /* blank, directive, document marker, block-sequence item */
        char *colon = s;
        while ((colon = strchr(colon, ':')) != NULL && colon[1] != '\0' && !isspace((unsigned char)colon[1]))
            colon++;
        if (colon == NULL)
            return fail(d, SFM_E_FORMAT, NULL, "line %d: expected 'key: value'", lineno);
        *colon = '\0';
        char *key = trim(s), *val = trim(colon + 1);
        if (strncmp(val, "!!", 2) == 0) { /* a type tag such as !!opencv-matrix */
            while (*val && !isspace((unsigned char)*val))
                val++;
            val = trim(val);
        }
        while (depth > 0 && indents[depth - 1] >= indent)
            depth--;
        char full[CF_KEY * 2] = "";
        for (int k = 0; k < depth; k++) {
            strcat(full, keys[k]);
            strcat(full, ".");
        }
        if (strlen(full) + strlen(key) >= CF_KEY)
            return fail(d, SFM_E_CAPACITY, key, "key too long");
        strcat(full, key);
        if (*val == '\0') {
            if (depth == CF_DEPTH)
                return fail(d, SFM_E_CAPACITY, full, "nested too deeply");
            snprintf(keys[depth], CF_KEY, "%s", key);
            indents[depth++] = indent;
            continue;
        }
        if (*val == '{')
            return fail(d, SFM_E_UNSUPPORTED, full, "flow mappings are not read here; write the "
                                                    "block style");
        size_t n = strlen(val);
        if (n >= 2 && (val[0] == '"' || val[0] == '\'') && val[n - 1] == val[0]) {
            val[n - 1] = '\0';
            val++;
            n -= 2;
        }
        if (*val == '[' && strchr(val, ']') == NULL) {
            snprintf(pending_key, sizeof pending_key, "%s", full);
            if (n >= sizeof pending)
                return fail(d, SFM_E_CAPACITY, full, "value too long");
            memcpy(pending, val, n);
            pending_len = n;
            continue;
        }
        int st = add(d, full, val, n);
        if (st < 0)
            return st;
    }
    if (pending_key[0])
        return fail(d, SFM_E_FORMAT, pending_key, "list not closed with ']'");
    return SFM_OK;
}

/* ---- OpenCV XML ----------------------------------------------------------- */

/* The element at *p ("<name ...>content</name>"): name, content span; *p
 * moves past it. 0 at the parent's end or the end of text, -1 malformed. */
static int xml_next(const char **p, char *name, size_t name_cap, const char **c0, const char **c1)
{
    const char *s = *p;
    for (;;) {
        while (*s && *s != '<')
            s++;
        if (*s == '\0')
            return 0;
        if (strncmp(s, "<!--", 4) == 0) {
            const char *e = strstr(s, "-->");
            if (e == NULL)
                return -1;
            s = e + 3;
            continue;
        }
        if (s[1] == '?') {
            const char *e = strstr(s, "?>");
            if (e == NULL)
                return -1;
            s = e + 2;
            continue;
        }
        break;
    }
    if (s[1] == '/')
        return 0;
    size_t k = 0;
    s++;
    while (*s && !isspace((unsigned char)*s) && *s != '>' && *s != '/') {
        if (k + 1 >= name_cap)
            return -1;
        name[k++] = *s++;
    }
    name[k] = '\0';
    const char *gt = strchr(s, '>');
    if (gt == NULL || k == 0)
        return -1;
    if (gt[-1] == '/') { /* <empty/> */
        *c0 = *c1 = gt;
        *p = gt + 1;
        return 1;
    }
    char close[CF_KEY + 4];
    snprintf(close, sizeof close, "</%s>", name);
    const char *end = strstr(gt + 1, close);
    if (end == NULL)
        return -1;
    *c0 = gt + 1;
    *c1 = end;
    *p = end + strlen(close);
    return 1;
}

static int parse_xml(cf_doc *d, const char *text)
{
    const char *p = text, *c0, *c1;
    char name[CF_KEY];
    if (xml_next(&p, name, sizeof name, &c0, &c1) != 1 || strcmp(name, "opencv_storage") != 0)
        return fail(d, SFM_E_FORMAT, NULL, "not an OpenCV FileStorage XML file");
    const char *q = c0;
    int r;
    const char *v0, *v1;
    while ((r = xml_next(&q, name, sizeof name, &v0, &v1)) == 1 && q <= c1) {
        const char *lt = memchr(v0, '<', (size_t)(v1 - v0));
        if (lt == NULL) {
            int st = add(d, name, v0, (size_t)(v1 - v0));
            if (st < 0)
                return st;
            continue;
        }
        const char *u = v0, *w0, *w1;
        char child[CF_KEY], full[2 * CF_KEY + 2];
        int rc;
        while ((rc = xml_next(&u, child, sizeof child, &w0, &w1)) == 1 && u <= v1) {
            snprintf(full, sizeof full, "%s.%s", name, child);
            int st = add(d, full, w0, (size_t)(w1 - w0));
            if (st < 0)
                return st;
        }
        if (rc < 0)
            return fail(d, SFM_E_FORMAT, name, "malformed XML");
    }
    if (r < 0)
        return fail(d, SFM_E_FORMAT, NULL, "malformed XML");
    for (int i = 0; i < d->n; i++) { /* values without the quotes OpenCV writes around strings */
        char *v = trim(d->e[i].val);
        size_t n = strlen(v);
        if (n >= 2 && v[0] == '"' && v[n - 1] == '"') {
            v[n - 1] = '\0';
            v++;
        }
        memmove(d->e[i].val, v, strlen(v) + 1);
    }
    return SFM_OK;
}

/* ---- KITTI ---------------------------------------------------------------- */

static int count_numbers(const char *s)
{
    int n = 0;
    char *end;
    for (;;) {
        while (isspace((unsigned char)*s))
            s++;
        if (*s == '\0')
            return n;
        strtod(s, &end);
        if (end == s)
            return -1;
        s = end;
        n++;
    }
}

static int kitti_label(const char *s, size_t *len)
{
    size_t k = 0;
    while (isalnum((unsigned char)s[k]) || s[k] == '_')
        k++;
    if (k == 0 || s[k] != ':')
        return 0;
    *len = k;
    return 1;
}

static int looks_kitti(const char *text)
{
    while (*text && (isspace((unsigned char)*text) || *text == '#')) {
        if (*text == '#')
            while (*text && *text != '\n')
                text++;
        else
            text++;
    }
    char line[CF_VAL];
    size_t k = strcspn(text, "\n");
    if (k >= sizeof line)
        return 0;
    memcpy(line, text, k);
    line[k] = '\0';
    size_t len;
    if (kitti_label(line, &len)) {
        static const char *const heads[] = {"P0", "P1", "P2", "P3", "P_rect_", "K_", "S_", "R_", "calib_time"};
        for (size_t i = 0; i < sizeof heads / sizeof heads[0]; i++)
            if (strncmp(line, heads[i], strlen(heads[i])) == 0)
                return 1;
        return 0;
    }
    return count_numbers(line) == 12;
}

static int parse_kitti(cf_doc *d, char *text)
{
    char *save = NULL;
    int bare = 0;
    for (char *line = strtok_r(text, "\n", &save); line; line = strtok_r(NULL, "\n", &save)) {
        char *s = trim(line);
        if (*s == '\0' || *s == '#')
            continue;
        size_t len;
        char key[CF_KEY];
        const char *val = s;
        if (kitti_label(s, &len)) {
            if (len >= sizeof key)
                return fail(d, SFM_E_CAPACITY, NULL, "label too long");
            memcpy(key, s, len);
            key[len] = '\0';
            val = s + len + 1;
            if (strcmp(key, "calib_time") == 0)
                continue;
        } else {
            snprintf(key, sizeof key, "P%d", bare++);
        }
        int st = add(d, key, val, strlen(val));
        if (st < 0)
            return st;
    }
    return SFM_OK;
}

/* ---- fields --------------------------------------------------------------- */

/* Up to cap numbers of a value: "[a, b, c]", "a b c" or multi-line lists. */
static int numbers(cf_doc *d, const char *field, const char *val, double *out, int cap, int *n)
{
    if (val == NULL)
        return fail(d, SFM_E_FORMAT, field, "missing");
    int k = 0;
    const char *s = val;
    for (;;) {
        while (isspace((unsigned char)*s) || *s == ',' || *s == '[' || *s == ']')
            s++;
        if (*s == '\0')
            break;
        char *end;
        double v = strtod(s, &end);
        if (end == s)
            return fail(d, SFM_E_FORMAT, field, "expected numbers, got \"%.40s\"", s);
        if (!isfinite(v))
            return fail(d, SFM_E_FORMAT, field, "holds a NaN or an infinity");
        if (k == cap)
            return fail(d, SFM_E_FORMAT, field, "more than %d numbers", cap);
        out[k++] = v;
        s = end;
    }
    *n = k;
    return SFM_OK;
}

static int exactly(cf_doc *d, const char *field, const char *val, double *out, int want)
{
    double tmp[16];
    int n = 0, st = numbers(d, field, val, tmp, 16, &n);
    if (st < 0)
        return st;
    if (n != want)
        return fail(d, SFM_E_FORMAT, field, "expected %d numbers, got %d", want, n);
    memcpy(out, tmp, (size_t)want * sizeof(double));
    return SFM_OK;
}

/* A matrix field: key.data (with key.rows, key.cols checked) or key itself. */
static int matrix(cf_doc *d, const char *key, double *out, int cap, int *n)
{
    char k[CF_KEY + 8];
    snprintf(k, sizeof k, "%s.data", key);
    const char *data = get(d, k);
    if (data == NULL && get(d, key) == NULL) {
        snprintf(k, sizeof k, "%s.rows", key);
        if (get(d, k) != NULL) {
            snprintf(k, sizeof k, "%s.data", key);
            return fail(d, SFM_E_FORMAT, k, "missing");
        }
        return fail(d, SFM_E_FORMAT, key, "missing");
    }
    int st = numbers(d, key, data ? data : get(d, key), out, cap, n);
    if (st < 0 || data == NULL)
        return st;
    char kr[CF_KEY + 8], kc[CF_KEY + 8];
    snprintf(kr, sizeof kr, "%s.rows", key);
    snprintf(kc, sizeof kc, "%s.cols", key);
    const char *r = get(d, kr), *c = get(d, kc);
    if (r != NULL && c != NULL && atoi(r) * atoi(c) != *n)
        return fail(d, SFM_E_FORMAT, key, "rows x cols is %s x %s but data holds %d numbers", r, c, *n);
    return SFM_OK;
}

static int positive_int(cf_doc *d, const char *field, double v, int *out)
{
    if (!(v >= 1 && v <= 1e6) || v != floor(v))
        return fail(d, SFM_E_FORMAT, field, "expected a positive integer, got %g", v);
    *out = (int)v;
    return SFM_OK;
}

static int finish(cf_doc *d, const char *field, sfm_camera *c)
{
    int st = sfm_camera_validate(c);
    if (st < 0)
        return fail(d, SFM_E_FORMAT, field, "not a valid camera (%s)", sfm_status_str(st));
    return SFM_OK;
}

static int lower_eq(const char *a, const char *b)
{
    if (a == NULL)
        return 0;
    for (; *a && *b; a++, b++)
        if (tolower((unsigned char)*a) != *b)
            return 0;
    return *a == '\0' && *b == '\0';
}

/* Brown from OpenCV's 4, 5, 8, 12 or 14 entries (the terms past k3 zero) or
 * fisheye from 4. */
static int set_dist(cf_doc *d, const char *field, const double *v, int n, int fisheye, sfm_camera *c)
{
    if (n == 0) {
        c->model = SFM_CAMERA_PINHOLE;
        return SFM_OK;
    }
    if (fisheye) {
        if (n != 4)
            return fail(d, SFM_E_FORMAT, field, "fisheye needs 4 coefficients, got %d", n);
        c->model = SFM_CAMERA_FISHEYE;
    } else {
        if (n != 4 && n != 5 && n != 8 && n != 12 && n != 14)
            return fail(d, SFM_E_FORMAT, field, "expected 4, 5, 8, 12 or 14 coefficients, got %d", n);
        for (int k = 5; k < n; k++)
            if (v[k] != 0)
                return fail(d, SFM_E_UNSUPPORTED, field, "coefficient %d is not 0: the Brown model has "
                                                         "k1, k2, p1, p2, k3 only", k + 1);
        c->model = SFM_CAMERA_BROWN;
    }
    for (int k = 0; k < n && k < 5; k++)
        c->dist[k] = v[k];
    return SFM_OK;
}

static int K_entries(cf_doc *d, const char *field, const double *K, sfm_camera *c)
{
    if (K[1] != 0 || K[3] != 0 || K[6] != 0 || K[7] != 0 || K[8] != 1)
        return fail(d, SFM_E_FORMAT, field, "expected [fx, 0, cx, 0, fy, cy, 0, 0, 1]");
    c->fx = K[0];
    c->fy = K[4];
    c->cx = K[2];
    c->cy = K[5];
    return SFM_OK;
}

static int read_opencv(cf_doc *d, sfm_camera *c, int *w, int *h)
{
    static const char *const knames[] = {"camera_matrix", "cameraMatrix", "K", "intrinsic_matrix"};
    static const char *const dnames[] = {"distortion_coefficients", "distCoeffs", "dist_coeffs", "D",
                                         "distortion"};
    const char *kn = knames[0], *dn = dnames[0];
    char key[CF_KEY + 8];
    for (size_t i = 0; i < sizeof knames / sizeof knames[0]; i++) {
        snprintf(key, sizeof key, "%s.data", knames[i]);
        if (get(d, knames[i]) || get(d, key)) {
            kn = knames[i];
            break;
        }
    }
    for (size_t i = 0; i < sizeof dnames / sizeof dnames[0]; i++) {
        snprintf(key, sizeof key, "%s.data", dnames[i]);
        if (get(d, dnames[i]) || get(d, key)) {
            dn = dnames[i];
            break;
        }
    }
    double K[16], D[16];
    int nk = 0, nd = 0, st = matrix(d, kn, K, 16, &nk);
    if (st < 0)
        return st;
    if (nk != 9)
        return fail(d, SFM_E_FORMAT, kn, "expected 9 numbers, got %d", nk);
    st = K_entries(d, kn, K, c);
    if (st < 0)
        return st;
    const char *model = get(d, "distortion_model");
    const char *fm = get(d, "fisheye_model");
    int fisheye = (fm != NULL && atoi(fm) != 0) || lower_eq(model, "fisheye") ||
                  lower_eq(model, "equidistant") || lower_eq(model, "kannala_brandt");
    if (model != NULL && !fisheye && !lower_eq(model, "plumb_bob") &&
        !lower_eq(model, "rational_polynomial") && !lower_eq(model, "radtan") &&
        !lower_eq(model, "radial-tangential") && !lower_eq(model, "none") && model[0] != '\0')
        return fail(d, SFM_E_UNSUPPORTED, "distortion_model", "unsupported model '%s'", model);
    snprintf(key, sizeof key, "%s.data", dn);
    if (get(d, dn) || get(d, key)) {
        st = matrix(d, dn, D, 16, &nd);
        if (st < 0)
            return st;
    } else if (model != NULL && model[0] != '\0' && !lower_eq(model, "none")) {
        return fail(d, SFM_E_FORMAT, dn, "missing");
    }
    st = set_dist(d, dn, D, nd, fisheye, c);
    if (st < 0)
        return st;
    const char *ws = get(d, "image_width"), *hs = get(d, "image_height");
    if ((ws == NULL) != (hs == NULL))
        return fail(d, SFM_E_FORMAT, ws ? "image_height" : "image_width", "missing");
    if (ws != NULL) {
        double v;
        if ((st = exactly(d, "image_width", ws, &v, 1)) < 0 || (st = positive_int(d, "image_width", v, w)) < 0)
            return st;
        if ((st = exactly(d, "image_height", hs, &v, 1)) < 0 || (st = positive_int(d, "image_height", v, h)) < 0)
            return st;
    }
    return finish(d, kn, c);
}

/* Kalibr camN block (prefix "camN.") or EuRoC sensor.yaml (prefix ""). */
static int read_kalibr(cf_doc *d, const char *prefix, const char *dist_key, sfm_camera *c, int *w, int *h)
{
    char f[CF_KEY + 32];
#define FIELD(name) (snprintf(f, sizeof f, "%s%s", prefix, name), f)
    const char *model = get(d, FIELD("camera_model"));
    if (model == NULL)
        return fail(d, SFM_E_FORMAT, f, "missing");
    if (strcmp(model, "pinhole") != 0)
        return fail(d, SFM_E_UNSUPPORTED, f, "unsupported projection '%s' (only pinhole)", model);
    double in[4], dist[4];
    int st = exactly(d, FIELD("intrinsics"), get(d, FIELD("intrinsics")), in, 4);
    if (st < 0)
        return st;
    c->fx = in[0];
    c->fy = in[1];
    c->cx = in[2];
    c->cy = in[3];
    const char *dm = get(d, FIELD("distortion_model"));
    if (dm == NULL)
        return fail(d, SFM_E_FORMAT, f, "missing");
    if (lower_eq(dm, "radtan") || lower_eq(dm, "radial-tangential") || lower_eq(dm, "plumb_bob"))
        c->model = SFM_CAMERA_BROWN;
    else if (lower_eq(dm, "equidistant") || lower_eq(dm, "equi") || lower_eq(dm, "fisheye"))
        c->model = SFM_CAMERA_FISHEYE;
    else if (lower_eq(dm, "none"))
        c->model = SFM_CAMERA_PINHOLE;
    else
        return fail(d, SFM_E_UNSUPPORTED, f, "unsupported model '%s'", dm);
    if (c->model != SFM_CAMERA_PINHOLE) {
        st = exactly(d, FIELD(dist_key), get(d, FIELD(dist_key)), dist, 4);
        if (st < 0)
            return st;
        for (int k = 0; k < 4; k++)
            c->dist[k] = dist[k];
    }
    const char *res = get(d, FIELD("resolution"));
    if (res != NULL) {
        double wh[2];
        if ((st = exactly(d, f, res, wh, 2)) < 0 || (st = positive_int(d, f, wh[0], w)) < 0 ||
            (st = positive_int(d, f, wh[1], h)) < 0)
            return st;
    }
    return finish(d, FIELD("intrinsics"), c);
#undef FIELD
}

static int read_kitti(cf_doc *d, const char *camera, sfm_camera *c, int *w, int *h)
{
    /* the first camera row, or the one named: "P2", "P_rect_02", "02" */
    for (int i = 0; i < d->n; i++) {
        const char *k = d->e[i].key;
        int proj = (k[0] == 'P' && isdigit((unsigned char)k[1]) && k[2] == '\0') || strncmp(k, "P_rect_", 7) == 0;
        int raw = strncmp(k, "K_", 2) == 0;
        if (!proj && !raw)
            continue;
        const char *name = raw ? k + 2 : k;
        if (camera != NULL && strcmp(camera, name) != 0)
            continue;
        double v[12];
        int st = exactly(d, k, d->e[i].val, v, raw ? 9 : 12);
        if (st < 0)
            return st;
        char sk[CF_KEY + 8];
        if (proj) {
            if (v[1] != 0 || v[4] != 0 || v[8] != 0 || v[9] != 0 || v[10] != 1)
                return fail(d, SFM_E_FORMAT, k, "not a rectified projection matrix K [I | t]");
            c->model = SFM_CAMERA_PINHOLE;
            c->fx = v[0];
            c->fy = v[5];
            c->cx = v[2];
            c->cy = v[6];
            snprintf(sk, sizeof sk, "S_rect_%s", k + 7);
        } else {
            if ((st = K_entries(d, k, v, c)) < 0)
                return st;
            char dk[CF_KEY + 8];
            snprintf(dk, sizeof dk, "D_%s", name);
            double D[16];
            int nd = 0;
            if ((st = numbers(d, dk, get(d, dk), D, 16, &nd)) < 0 || (st = set_dist(d, dk, D, nd, 0, c)) < 0)
                return st;
            snprintf(sk, sizeof sk, "S_%s", name);
        }
        const char *s = strncmp(k, "P_rect_", 7) == 0 || raw ? get(d, sk) : NULL;
        if (s != NULL) {
            double wh[2];
            if ((st = exactly(d, sk, s, wh, 2)) < 0 || (st = positive_int(d, sk, wh[0], w)) < 0 ||
                (st = positive_int(d, sk, wh[1], h)) < 0)
                return st;
        }
        return finish(d, k, c);
    }
    if (camera != NULL)
        return fail(d, SFM_E_FORMAT, camera, "no such camera row");
    return fail(d, SFM_E_FORMAT, "P0", "missing: no projection (P0..P3) or K_xx rows");
}

/* The Kalibr camera blocks: the distinct "camN" prefixes in file order. */
static int kalibr_camera(const cf_doc *d, const char *camera, char *prefix, size_t cap)
{
    int found = 0;
    for (int i = 0; i < d->n; i++) {
        const char *k = d->e[i].key;
        if (strncmp(k, "cam", 3) != 0 || !isdigit((unsigned char)k[3]))
            continue;
        size_t j = 3;
        while (isdigit((unsigned char)k[j]))
            j++;
        if (k[j] != '.')
            continue;
        found = 1;
        if (camera == NULL || (strlen(camera) == j && strncmp(camera, k, j) == 0)) {
            snprintf(prefix, cap, "%.*s.", (int)j, k);
            return 1;
        }
    }
    return found ? -1 : 0;
}

/* The parse proper, on a writable NUL-terminated copy of the text. */
static int parse_text(cf_doc *d, char *text, const char *camera, sfm_camera *c, int *w, int *h)
{
    const char *s = text;
    while (isspace((unsigned char)*s))
        s++;
    int st;
    if (*s == '<') {
        st = parse_xml(d, text);
        return st < 0 ? st : read_opencv(d, c, w, h);
    }
    if (looks_kitti(text)) {
        st = parse_kitti(d, text);
        return st < 0 ? st : read_kitti(d, camera, c, w, h);
    }
    st = parse_yaml(d, text);
    if (st < 0)
        return st;
    char prefix[CF_KEY];
    int kc = kalibr_camera(d, camera, prefix, sizeof prefix);
    if (kc < 0)
        return fail(d, SFM_E_FORMAT, camera, "no such camera in the camchain");
    if (kc > 0)
        return read_kalibr(d, prefix, "distortion_coeffs", c, w, h);
    if (get(d, "sensor_type") != NULL || (get(d, "intrinsics") && get(d, "camera_model"))) {
        const char *type = get(d, "sensor_type");
        if (type != NULL && strcmp(type, "camera") != 0)
            return fail(d, SFM_E_FORMAT, "sensor_type", "not a camera ('%s')", type);
        return read_kalibr(d, "", "distortion_coefficients", c, w, h);
    }
    return read_opencv(d, c, w, h);
}

int calib_text_read(const char *name, const char *text, size_t len, const char *camera, sfm_camera *cam,
                    int *width, int *height, char *err, size_t err_size)
{
    cf_doc d = {NULL, 0, name ? name : "(text)", err, err_size};
    if (err != NULL && err_size > 0)
        err[0] = '\0';
    if (text == NULL || cam == NULL)
        return fail(&d, SFM_E_ARGUMENT, NULL, "no text or no camera to fill");
    if (len > CF_MAX_FILE)
        return fail(&d, SFM_E_CAPACITY, NULL, "larger than %d bytes", CF_MAX_FILE);
    if (memchr(text, '\0', len) != NULL)
        return fail(&d, SFM_E_FORMAT, NULL, "not a text file");
    char *copy = malloc(len + 1);
    d.e = malloc(sizeof(cf_entry) * CF_MAX_ENTRIES);
    int st;
    sfm_camera c;
    int w = 0, h = 0;
    memset(&c, 0, sizeof c);
    if (copy == NULL || d.e == NULL) {
        st = fail(&d, SFM_E_IO, NULL, "out of memory");
    } else {
        memcpy(copy, text, len);
        copy[len] = '\0';
        st = parse_text(&d, copy, camera, &c, &w, &h);
    }
    if (st == SFM_OK) {
        *cam = c;
        if (width != NULL)
            *width = w;
        if (height != NULL)
            *height = h;
    }
    free(copy);
    free(d.e);
    return st;
}

int calib_file_read(const char *path, const char *camera, sfm_camera *cam, int *width, int *height,
                    char *err, size_t err_size)
{
    cf_doc d = {NULL, 0, path ? path : "(null)", err, err_size};
    if (err != NULL && err_size > 0)
        err[0] = '\0';
    if (path == NULL || cam == NULL)
        return fail(&d, SFM_E_ARGUMENT, NULL, "no file or no camera to fill");
    FILE *f = fopen(path, "rb");
    if (f == NULL)
        return fail(&d, SFM_E_IO, NULL, "cannot be opened");
    char *text = malloc(CF_MAX_FILE + 1);
    size_t n = text ? fread(text, 1, CF_MAX_FILE + 1, f) : 0;
    int bad_read = ferror(f);
    fclose(f);
    int st;
    if (text == NULL)
        st = fail(&d, SFM_E_IO, NULL, "out of memory");
    else if (bad_read)
        st = fail(&d, SFM_E_IO, NULL, "read error");
    else if (n > CF_MAX_FILE)
        st = fail(&d, SFM_E_CAPACITY, NULL, "larger than %d bytes", CF_MAX_FILE);
    else
        st = calib_text_read(path, text, n, camera, cam, width, height, err, err_size);
    free(text);
    return st;
}
