/* PGM/PPM and manifest parsers, against hand-built files with known
 * contents, and their contracts. */
#include <stdlib.h>
#include <string.h>

#include "cap_test.h"
#include "sfm_test.h"

SFM_TEST(pnm_p5_with_comments)
{
    static const char hdr[] = "P5\n# made by hand\n3 2 # width height\n255\n";
    uint8_t buf[64];
    memcpy(buf, hdr, sizeof hdr - 1);
    const uint8_t px[6] = {0, 1, 2, 253, 254, 255};
    memcpy(buf + sizeof hdr - 1, px, 6);
    size_t len = sizeof hdr - 1 + 6;
    sfm_image_header h;
    SFM_CHECK_EQ_INT(sfm_pnm_parse_header(buf, len, &h), SFM_OK);
    SFM_CHECK_EQ_INT(h.width, 3);
    SFM_CHECK_EQ_INT(h.height, 2);
    SFM_CHECK_EQ_INT(h.channels, 1);
    SFM_CHECK_EQ_INT(h.maxval, 255);
    SFM_CHECK_EQ_INT(h.binary, 1);
    SFM_CHECK_EQ_INT((long)h.data_offset, (long)(sizeof hdr - 1));
    uint8_t out[2 * 5];
    memset(out, 0xAA, sizeof out);
    SFM_CHECK_EQ_INT(sfm_pnm_decode_gray(buf, len, out, 3, 2, 5), SFM_OK);
    for (int y = 0; y < 2; y++)
        for (int x = 0; x < 3; x++)
            SFM_CHECK_EQ_INT(out[y * 5 + x], px[y * 3 + x]);
    SFM_CHECK_EQ_INT(out[3], 0xAA); /* padding untouched */
    /* One byte short of the raster. */
    SFM_CHECK_EQ_INT(sfm_pnm_parse_header(buf, len - 1, &h), SFM_E_FORMAT);
}

SFM_TEST(pnm_ascii_and_16bit_scaled)
{
    /* P2 with maxval 15: v8 = round(v * 255 / 15) = 17 v. */
    static const char p2[] = "P2\n2 2\n15\n0 15\n7\n8\n";
    uint8_t out[4];
    SFM_CHECK_EQ_INT(sfm_pnm_decode_gray((const uint8_t *)p2, sizeof p2 - 1, out, 2, 2, 2), SFM_OK);
    SFM_CHECK_EQ_INT(out[0], 0);
    SFM_CHECK_EQ_INT(out[1], 255);
    SFM_CHECK_EQ_INT(out[2], 119);
    SFM_CHECK_EQ_INT(out[3], 136);
    /* P5, 16-bit big-endian, maxval 65535: v8 = round(v * 255 / 65535). */
    uint8_t b[32];
    static const char h16[] = "P5 2 1 65535\n";
    memcpy(b, h16, sizeof h16 - 1);
    size_t o = sizeof h16 - 1;
    b[o] = 0x80; b[o + 1] = 0x00; /* 32768 -> 127.5 -> 128 */
    b[o + 2] = 0xFF; b[o + 3] = 0xFF;
    SFM_CHECK_EQ_INT(sfm_pnm_decode_gray(b, o + 4, out, 2, 1, 2), SFM_OK);
    SFM_CHECK_EQ_INT(out[0], 128);
    SFM_CHECK_EQ_INT(out[1], 255);
}

SFM_TEST(pnm_ppm_uses_bt601_luma)
{
    uint8_t b[64];
    static const char h6[] = "P6\n4 1\n255\n";
    memcpy(b, h6, sizeof h6 - 1);
    size_t o = sizeof h6 - 1;
    const uint8_t rgb[12] = {255, 0, 0, 0, 255, 0, 0, 0, 255, 255, 255, 255};
    memcpy(b + o, rgb, 12);
    uint8_t out[4];
    SFM_CHECK_EQ_INT(sfm_pnm_decode_gray(b, o + 12, out, 4, 1, 4), SFM_OK);
    /* 0.299*255 = 76.2, 0.587*255 = 149.7, 0.114*255 = 29.1, white 255 */
    SFM_CHECK(abs(out[0] - 76) <= 1);
    SFM_CHECK(abs(out[1] - 150) <= 1);
    SFM_CHECK(abs(out[2] - 29) <= 1);
    SFM_CHECK_EQ_INT(out[3], 255);
}

SFM_TEST(pnm_rejects_bad_headers)
{
    sfm_image_header h;
    const char *bad[] = {"", "P", "P7\n1 1\n255\n ", "P5", "P5\n", "P5\n0 1\n255\n ",
                         "P5\n1 0\n255\n ", "P5\n1 1\n0\n ", "P5\n1 1\n65536\n ",
                         "P5\n1 1 255", "P5\n-1 1\n255\n ", "P51 1 255\n ", "Q5\n1 1\n255\n "};
    for (size_t i = 0; i < sizeof bad / sizeof bad[0]; i++) {
        sfm_test_fill_canary(&h, sizeof h);
        SFM_CHECK_MSG(sfm_pnm_parse_header((const uint8_t *)bad[i], strlen(bad[i]), &h) ==
                          SFM_E_FORMAT, "case %zu", i);
        SFM_CHECK(sfm_test_canary_intact(&h, sizeof h));
    }
    static const char huge[] = "P5\n20000 1\n255\n ";
    SFM_CHECK_EQ_INT(sfm_pnm_parse_header((const uint8_t *)huge, sizeof huge - 1, &h),
                     SFM_E_CAPACITY);
    static const char overflow[] = "P5\n99999999999999999999 1\n255\n ";
    SFM_CHECK_EQ_INT(sfm_pnm_parse_header((const uint8_t *)overflow, sizeof overflow - 1, &h),
                     SFM_E_FORMAT);
    SFM_CHECK_EQ_INT(sfm_pnm_parse_header(NULL, 3, &h), SFM_E_ARGUMENT);
    SFM_CHECK_EQ_INT(sfm_pnm_parse_header((const uint8_t *)"P5", 2, NULL), SFM_E_ARGUMENT);
    /* Decode into the wrong size: refused, nothing written. */
    static const char ok[] = "P5\n2 2\n255\n\1\2\3\4";
    uint8_t out[16];
    sfm_test_fill_canary(out, sizeof out);
    SFM_CHECK_EQ_INT(sfm_pnm_decode_gray((const uint8_t *)ok, sizeof ok - 1, out, 2, 3, 2),
                     SFM_E_FORMAT);
    SFM_CHECK_EQ_INT(sfm_pnm_decode_gray((const uint8_t *)ok, sizeof ok - 1, out, 2, 2, 1),
                     SFM_E_ARGUMENT);
    SFM_CHECK(sfm_test_canary_intact(out, sizeof out));
    /* ASCII sample missing. */
    static const char p2short[] = "P2\n2 2\n255\n1 2 3";
    SFM_CHECK_EQ_INT(sfm_pnm_decode_gray((const uint8_t *)p2short, sizeof p2short - 1, out, 2, 2, 2),
                     SFM_E_FORMAT);
}

SFM_TEST(manifest_three_columns_and_header)
{
    static const char m[] = "sequence,timestamp_ns,file\r\n"
                            "0,1000,a.pgm\r\n"
                            "# a comment\n"
                            "\n"
                            "  2 , 3000 , sub/b.png \n"
                            "5,3000,c.jpg";
    SFM_CHECK_EQ_INT(sfm_manifest_parse(m, sizeof m - 1, NULL, 0), 3);
    sfm_manifest_entry e[3];
    SFM_CHECK_EQ_INT(sfm_manifest_parse(m, sizeof m - 1, e, 3), 3);
    SFM_CHECK_EQ_INT(e[0].sequence, 0);
    SFM_CHECK_EQ_INT(e[0].timestamp_ns, 1000);
    SFM_CHECK(strcmp(e[0].file, "a.pgm") == 0);
    SFM_CHECK_EQ_INT(e[1].sequence, 2);
    SFM_CHECK(strcmp(e[1].file, "sub/b.png") == 0);
    SFM_CHECK_EQ_INT(e[2].sequence, 5);
    SFM_CHECK_EQ_INT(e[2].timestamp_ns, 3000);
    SFM_CHECK(strcmp(e[2].file, "c.jpg") == 0);
}

SFM_TEST(manifest_euroc_two_columns)
{
    static const char m[] = "#timestamp [ns],filename\n"
                            "1403636579763555584,1403636579763555584.png\n"
                            "1403636579813555456,1403636579813555456.png\n";
    sfm_manifest_entry e[2];
    SFM_CHECK_EQ_INT(sfm_manifest_parse(m, sizeof m - 1, e, 2), 2);
    SFM_CHECK(e[0].timestamp_ns == 1403636579763555584LL);
    SFM_CHECK_EQ_INT(e[0].sequence, 0);
    SFM_CHECK_EQ_INT(e[1].sequence, 1);
    SFM_CHECK(strcmp(e[1].file, "1403636579813555456.png") == 0);
}

SFM_TEST(manifest_rejects_bad_rows_and_writes_nothing)
{
    const char *bad[] = {
        "0,100,a.pgm\n1,99,b.pgm\n",          /* time going back */
        "0,100,a.pgm\n0,200,b.pgm\n",         /* sequence not increasing */
        "0,100,../etc/passwd\n",              /* escapes the directory */
        "0,100,/abs.pgm\n",                   /* absolute */
        "0,100,\n",                           /* no file */
        "0,,a.pgm\n",                         /* empty timestamp */
        "100\n",                              /* one column */
        "0,1x0,a.pgm\n",                      /* not a number */
        "0,-5,a.pgm\n",                       /* negative */
        "0,1,2,a.pgm\n",                      /* four columns */
        "0,100,a.pgm\nheader,late,x\n",       /* header after data */
        "0,99999999999999999999,a.pgm\n",     /* overflow */
        "0,9223372036854775808,a.pgm\n",      /* above INT64_MAX */
        "0,100,a//b.pgm\n",                   /* empty component */
        "0,100,dir/\n",                       /* a directory */
    };
    sfm_manifest_entry e[4];
    for (size_t i = 0; i < sizeof bad / sizeof bad[0]; i++) {
        sfm_test_fill_canary(e, sizeof e);
        SFM_CHECK_MSG(sfm_manifest_parse(bad[i], strlen(bad[i]), e, 4) == SFM_E_FORMAT,
                      "case %zu", i);
        SFM_CHECK(sfm_test_canary_intact(e, sizeof e));
    }
    /* A name one byte too long. */
    static char longname[SFM_CAPTURE_PATH_MAX + 16];
    memcpy(longname, "0,1,", 4);
    memset(longname + 4, 'a', SFM_CAPTURE_PATH_MAX);
    longname[4 + SFM_CAPTURE_PATH_MAX] = '\0';
    SFM_CHECK_EQ_INT(sfm_manifest_parse(longname, strlen(longname), NULL, 0), SFM_E_FORMAT);
    longname[4 + SFM_CAPTURE_PATH_MAX - 1] = '\0'; /* exactly the longest */
    SFM_CHECK_EQ_INT(sfm_manifest_parse(longname, strlen(longname), NULL, 0), 1);
    /* Capacity and contracts. */
    static const char two[] = "0,1,a\n1,2,b\n";
    sfm_test_fill_canary(e, sizeof e);
    SFM_CHECK_EQ_INT(sfm_manifest_parse(two, sizeof two - 1, e, 1), SFM_E_CAPACITY);
    SFM_CHECK(sfm_test_canary_intact(e, sizeof e));
    SFM_CHECK_EQ_INT(sfm_manifest_parse(NULL, 0, NULL, 0), SFM_E_ARGUMENT);
    SFM_CHECK_EQ_INT(sfm_manifest_parse(two, sizeof two - 1, NULL, 2), SFM_E_ARGUMENT);
    SFM_CHECK_EQ_INT(sfm_manifest_parse(two, sizeof two - 1, e, -1), SFM_E_ARGUMENT);
    SFM_CHECK_EQ_INT(sfm_manifest_parse("", 0, NULL, 0), 0);
}
