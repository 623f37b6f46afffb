/* Internal: the BRIEF sampling pattern (generated, see tools/gen_brief_pattern.py). */
#ifndef SFM_FEATURES_BRIEF_PATTERN_H
#define SFM_FEATURES_BRIEF_PATTERN_H

#define SFM_BRIEF_PAIRS 256
/* Every point of the pattern lies within this radius of the patch centre. */
#define SFM_BRIEF_RADIUS 15

/* Rows x1, y1, x2, y2 (structure of arrays, so steering vectorises). */
extern const signed char sfmi_brief_pattern[4][SFM_BRIEF_PAIRS];

#endif
