/* Camera calibration files for the programs in firmware_examples/ (a tools
 * layer beside the library: it reads files, so it is not in the core).
 *
 * Formats, told apart by content (the same set and rules as Python's
 * libsfm.calib):
 *   OpenCV FileStorage YAML (%YAML:1.0, !!opencv-matrix) and XML, as
 *     cv2.FileStorage writes after calibrateCamera: camera_matrix (or
 *     cameraMatrix, K), distortion_coefficients (or distCoeffs, dist_coeffs,
 *     D), image_width, image_height; fisheye_model: 1 or distortion_model:
 *     fisheye / equidistant marks a cv2.fisheye calibration;
 *   ROS camera_info YAML: camera_matrix {rows, cols, data}, distortion_model
 *     (plumb_bob, rational_polynomial, equidistant), distortion_coefficients;
 *   Kalibr camchain: cam0, cam1, ... with camera_model pinhole, intrinsics
 *     [fu, fv, pu, pv], distortion_model radtan or equidistant,
 *     distortion_coeffs, resolution [w, h];
 *   EuRoC sensor.yaml: the same keys as Kalibr at the top level
 *     (distortion_model radial-tangential, distortion_coefficients);
 *   KITTI calib.txt: rows "P0: <12 numbers>" (or unlabelled rows of 12), K the
 *     left 3x3 of the rectified projection; calib_cam_to_cam.txt K_xx, D_xx,
 *     S_xx.
 * Radial-tangential is Brown-Conrady (SFM_CAMERA_BROWN); equidistant is
 * Kannala-Brandt (SFM_CAMERA_FISHEYE). The YAML understood is the block
 * style these programs write (flow lists may span lines); flow mappings are
 * refused with a message.
 */
#ifndef CALIB_FILE_H
#define CALIB_FILE_H

#include <stddef.h>

#include "sfm/sfm_camera.h"

/* Reads one camera of the file at path. camera selects one where the file
 * holds several ("cam1" for Kalibr, "P2" or "00" for KITTI); NULL: the
 * first. width and height (may be NULL) receive the image size, 0 when the
 * file has none. Returns SFM_OK; SFM_E_IO (cannot read), SFM_E_FORMAT (a
 * field missing or malformed), SFM_E_UNSUPPORTED (a model libsfm does not
 * have), SFM_E_CAPACITY (a file or a line too long), with a message naming
 * the file and the field in err (err_size bytes, may be 0). Nothing is
 * written to cam, width, height on failure. */
int calib_file_read(const char *path, const char *camera, sfm_camera *cam, int *width, int *height,
                    char *err, size_t err_size);

/* The same on a file's text held in memory (len bytes, need not end in a
 * NUL); name stands for the file in messages. */
int calib_text_read(const char *name, const char *text, size_t len, const char *camera, sfm_camera *cam,
                    int *width, int *height, char *err, size_t err_size);

#endif
