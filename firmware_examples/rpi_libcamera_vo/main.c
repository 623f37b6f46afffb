/* vo-libcamera: the vo-camera loop (firmware_examples/linux_v4l2_vo) with
 * libcamera's first camera as the default source, for a Raspberry Pi camera
 * module. Any source vo-camera takes still works as the first argument. */
#define VO_DEFAULT_SOURCE "libcamera"
#include "../linux_v4l2_vo/vo_main.c"
