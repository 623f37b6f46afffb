/* sfm-calib: prints the camera a calibration file gives, as the programs
 * here read it (calib_file.h): one line
 *   model fx fy cx cy d0 d1 d2 d3 d4 width height
 * model pinhole, brown or fisheye; numbers in full precision (%.17g); width
 * and height 0 when the file has no image size.
 * Exit status: 0 read, 1 the file cannot be read (the reason, naming the
 * file and the field, on stderr), 2 bad usage. */
#define _POSIX_C_SOURCE 200809L
#include <stdio.h>
#include <string.h>

#include "calib_file.h"

int main(int argc, char **argv)
{
    if (argc < 2 || argc > 3 || strcmp(argv[1], "--help") == 0) {
        fprintf(argc < 2 || argc > 3 ? stderr : stdout,
                "usage: sfm-calib FILE [CAMERA]\n"
                "Prints the camera of a calibration file: OpenCV FileStorage YAML/XML, ROS\n"
                "camera_info, Kalibr camchain (CAMERA: cam0, cam1, ...), EuRoC sensor.yaml,\n"
                "KITTI calib.txt (CAMERA: P0..P3, or 00.. for calib_cam_to_cam.txt).\n");
        return argc < 2 || argc > 3 ? 2 : 0;
    }
    sfm_camera cam;
    int w = 0, h = 0;
    char err[768];
    int st = calib_file_read(argv[1], argc == 3 ? argv[2] : NULL, &cam, &w, &h, err, sizeof err);
    if (st != SFM_OK) {
        fprintf(stderr, "sfm-calib: %s (%s)\n", err, sfm_status_str(st));
        return 1;
    }
    static const char *const names[] = {"pinhole", "brown", "fisheye"};
    printf("%s %.17g %.17g %.17g %.17g", names[cam.model], cam.fx, cam.fy, cam.cx, cam.cy);
    for (int k = 0; k < 5; k++)
        printf(" %.17g", cam.dist[k]);
    printf(" %d %d\n", w, h);
    return 0;
}
