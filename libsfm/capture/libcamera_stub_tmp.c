#include "capture/capture_impl.h"
int sfm_libcamera_list(char *ids, int max_ids, int id_len)
{ (void)ids; (void)max_ids; (void)id_len; return SFM_E_UNSUPPORTED; }
int sfm_capture_open_libcamera(const char *camera_id, const sfm_libcamera_options *opt, sfm_capture **out)
{ (void)camera_id; (void)opt; (void)out; return SFM_E_UNSUPPORTED; }
