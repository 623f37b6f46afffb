/* The replay manifest: CSV rows "sequence,timestamp_ns,file" or
 * "timestamp_ns,file" (the EuRoC / ASL layout "#timestamp [ns],filename"
 * reads as the latter). The whole text is checked before a row counts. */
#include <limits.h>
#include <string.h>

#include "capture/capture_impl.h"

static int is_blank(char c) { return c == ' ' || c == '\t' || c == '\r'; }

/* [b, e) trimmed of blanks. */
static void trim(const char **b, const char **e)
{
    while (*b < *e && is_blank(**b))
        (*b)++;
    while (*e > *b && is_blank((*e)[-1]))
        (*e)--;
}

static int parse_u64(const char *b, const char *e, uint64_t *out)
{
    if (b == e)
        return SFM_E_FORMAT;
    uint64_t v = 0;
    for (; b < e; b++) {
        if (*b < '0' || *b > '9')
            return SFM_E_FORMAT;
        unsigned d = (unsigned)(*b - '0');
        if (v > (UINT64_MAX - d) / 10)
            return SFM_E_FORMAT;
        v = v * 10 + d;
    }
    *out = v;
    return SFM_OK;
}

/* A relative name without "..", control bytes or backslashes. */
static int check_file(const char *b, const char *e)
{
    size_t n = (size_t)(e - b);
    if (n == 0 || n >= SFM_CAPTURE_PATH_MAX || *b == '/')
        return SFM_E_FORMAT;
    const char *comp = b;
    for (const char *p = b; p <= e; p++) {
        if (p == e || *p == '/') {
            if (p - comp == 2 && comp[0] == '.' && comp[1] == '.')
                return SFM_E_FORMAT;
            if (p - comp == 0 && p != e)
                return SFM_E_FORMAT; /* empty component: "a//b" or trailing '/' */
            comp = p + 1;
            continue;
        }
        unsigned char c = (unsigned char)*p;
        if (c < 0x20 || c == 0x7f || c == '\\' || c == '"')
            return SFM_E_FORMAT;
    }
    if (e[-1] == '/')
        return SFM_E_FORMAT;
    return SFM_OK;
}

static int parse(const char *text, size_t len, sfm_manifest_entry *out, int capacity)
{
    const int counting = out == NULL;
    const char *p = text, *end = text + len;
    int rows = 0, seen_data = 0;
    int64_t last_ts = 0;
    uint64_t last_seq = 0;
    while (p < end) {
        const char *eol = memchr(p, '\n', (size_t)(end - p));
        if (eol == NULL)
            eol = end;
        const char *b = p, *e = eol;
        p = eol < end ? eol + 1 : end;
        trim(&b, &e);
        if (b == e || *b == '#')
            continue;
        if (memchr(b, '\0', (size_t)(e - b)) != NULL)
            return SFM_E_FORMAT;
        if (*b < '0' || *b > '9') {
            if (seen_data)
                return SFM_E_FORMAT; /* a header only before the first row */
            seen_data = 1;
            continue;
        }
        seen_data = 1;
        const char *f[4];
        const char *fe[4];
        int nf = 0;
        const char *s = b;
        for (;;) {
            const char *c = memchr(s, ',', (size_t)(e - s));
            if (nf == 3)
                return SFM_E_FORMAT;
            f[nf] = s;
            fe[nf] = c ? c : e;
            trim(&f[nf], &fe[nf]);
            nf++;
            if (c == NULL)
                break;
            s = c + 1;
        }
        if (nf < 2)
            return SFM_E_FORMAT;
        uint64_t seq, ts;
        int k = 0;
        if (nf == 3) {
            if (parse_u64(f[0], fe[0], &seq) != SFM_OK)
                return SFM_E_FORMAT;
            k = 1;
        } else {
            seq = (uint64_t)rows;
        }
        if (parse_u64(f[k], fe[k], &ts) != SFM_OK || ts > (uint64_t)INT64_MAX)
            return SFM_E_FORMAT;
        if (check_file(f[k + 1], fe[k + 1]) != SFM_OK)
            return SFM_E_FORMAT;
        if (rows > 0 && ((int64_t)ts < last_ts || seq <= last_seq))
            return SFM_E_FORMAT;
        if (rows == INT_MAX)
            return SFM_E_CAPACITY;
        if (!counting) {
            if (rows >= capacity)
                return SFM_E_CAPACITY;
            sfm_manifest_entry *en = &out[rows];
            en->sequence = seq;
            en->timestamp_ns = (int64_t)ts;
            size_t n = (size_t)(fe[k + 1] - f[k + 1]);
            memcpy(en->file, f[k + 1], n);
            en->file[n] = '\0';
        }
        last_ts = (int64_t)ts;
        last_seq = seq;
        rows++;
    }
    return rows;
}

/* A counting pass validates everything first, so a failing call writes
 * nothing to out. */
int sfm_manifest_parse(const char *text, size_t len, sfm_manifest_entry *out, int capacity)
{
    if (text == NULL || capacity < 0 || (out == NULL && capacity != 0))
        return SFM_E_ARGUMENT;
    int n = parse(text, len, NULL, 0);
    if (n < 0 || out == NULL)
        return n;
    if (n > capacity)
        return SFM_E_CAPACITY;
    return parse(text, len, out, capacity);
}
