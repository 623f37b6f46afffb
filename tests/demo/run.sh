#!/bin/sh
# test-demo: runs the three-view demo program on the synthetic scene of
# tools/gen_demo_scene.py and checks its figures against the scene's ground
# truth, plus its exit statuses on bad input. Ends with "N passed, N failed".
#
# Bounds (measured on the seeded scene: rotation errors 0.07 and 0.15 deg,
# translation direction 0.49 and 0.66 deg, scale 0.15 %, median reprojection
# 0.30 px, 215 triplets, 212 inliers), with margin for another compiler or
# libm: rotation < 0.5 deg, translation direction < 2 deg, scale < 3 %,
# median reprojection < 1 px, at least 100 triplets and 90 % inliers.
#
#   sh tests/demo/run.sh BUILD/bin/three_view_demo BUILD/demo/synthetic
set -u
BIN=$1
DIR=$2
TMP=${TMPDIR:-/tmp}/sfm-test-demo.$$
mkdir -p "$TMP"
trap 'rm -rf "$TMP"' EXIT
pass=0
fail=0
check() { # name, then a shell condition
    name=$1
    shift
    if eval "$@"; then
        pass=$((pass + 1))
        echo "ok   $name"
    else
        fail=$((fail + 1))
        echo "FAIL $name ($*)"
    fi
}
# Field after a fixed prefix: num "prefix" [field index after it]
num() {
    awk -v p="$1" -v k="${2:-1}" '(i = index($0, p)) > 0 {
        split(substr($0, i + length(p)), f, " "); v = f[k]; gsub(/[,%]/, "", v); print v; exit }' "$TMP/out.txt"
}
lt() { awk -v a="$1" -v b="$2" 'BEGIN { exit !(a != "" && a + 0 == a && a < b) }'; }
abs_lt() { awk -v a="$1" -v b="$2" 'BEGIN { ok = a != "" && a + 0 == a; if (a < 0) a = -a; exit !(ok && a < b) }'; }

"$BIN" "$DIR" --gt "$DIR/ground_truth.txt" --ply "$TMP/points.ply" > "$TMP/out.txt" 2> "$TMP/err.txt"
rc=$?
cat "$TMP/out.txt" "$TMP/err.txt"
check "exit status 0 on the synthetic scene" '[ $rc -eq 0 ]'

trip=$(num "triplets after association: ")
inl=$(num "trifocal inliers: ")
check "at least 100 triplets (got $trip)" '[ "${trip:-0}" -ge 100 ]'
check "at least 90% inliers ($inl of $trip)" '[ $(( ${inl:-0} * 10 )) -ge $(( ${trip:-1} * 9 )) ]'
r2=$(num "rotation error: view 2 ")
r3=$(num "rotation error: view 2 " 5)
d2=$(num "translation direction error: view 2 ")
d3=$(num "translation direction error: view 2 " 5)
sc=$(num "scale |t3|/|t2|: estimated " 5 | tr -d '%')
re=$(num "median reprojection error of the inliers: ")
check "rotation error view 2 < 0.5 deg ($r2)" 'lt "$r2" 0.5'
check "rotation error view 3 < 0.5 deg ($r3)" 'lt "$r3" 0.5'
check "translation direction error view 2 < 2 deg ($d2)" 'lt "$d2" 2'
check "translation direction error view 3 < 2 deg ($d3)" 'lt "$d3" 2'
check "scale |t3|/|t2| within 3% ($sc %)" 'abs_lt "$sc" 3'
check "median reprojection error < 1 px ($re)" 'lt "$re" 1'
pl=$(num "inliers on one plane (homography 1-2 within 1.00 px): ")
check "plane share reported, no twin warning on the room ($pl inliers on one plane)" \
    '[ -n "$pl" ] && ! grep -q "^warning" "$TMP/out.txt"'
npts=$(sed -n 's/^element vertex //p' "$TMP/points.ply")
check "PLY holds the points in front ($npts)" '[ "${npts:-0}" -ge 90 ] && [ $(wc -l < "$TMP/points.ply") -eq $((npts + 7)) ]'

# Same seed, same input: the same figures, bit for bit in the printout.
"$BIN" "$DIR" --gt "$DIR/ground_truth.txt" 2>&1 | grep -v " ms" > "$TMP/again.txt"
grep -v " ms" "$TMP/out.txt" | grep -v "^points written" > "$TMP/first.txt"
check "deterministic: a second run prints the same figures" 'cmp -s "$TMP/first.txt" "$TMP/again.txt"'

# Failures are statuses, not crashes.
"$BIN" > /dev/null 2>&1
rc=$?
check "no directory: usage, exit 2" '[ $rc -eq 2 ]'
# No intrinsics: the camera is self-calibrated; the room's fx is 500 (its
# ground truth), the answer must land within 5 % or the run must fail.
"$BIN" "$DIR" > "$TMP/uncal.txt" 2>&1
rc=$?
f_uncal=$(sed -n 's/^  focal length \([0-9.]*\) px.*/\1/p' "$TMP/uncal.txt")
check "no intrinsics: self-calibrated, exit 0" '[ $rc -eq 0 ] && [ -n "$f_uncal" ]'
check "no intrinsics: focal length within 5 % of 500 px (got $f_uncal)" \
    'awk -v f="$f_uncal" "BEGIN { exit !(f > 475 && f < 525) }"'
"$BIN" "$DIR" --camera 500,500,319.5 > /dev/null 2>&1
rc=$?
check "bad --camera: exit 2" '[ $rc -eq 2 ]'
"$BIN" "$TMP/missing" --camera 500,500,319.5,239.5 > "$TMP/o2.txt" 2>&1
rc=$?
check "missing directory: exit 1 with the status named" '[ $rc -eq 1 ] && grep -q "(-11)" "$TMP/o2.txt"'
mkdir -p "$TMP/two"
cp "$DIR"/view1.pgm "$DIR"/view2.pgm "$TMP/two/"
printf 'sequence,timestamp_ns,file\n0,0,view1.pgm\n1,1,view2.pgm\n' > "$TMP/two/manifest.csv"
"$BIN" "$TMP/two" --camera 500,500,319.5,239.5 > "$TMP/o3.txt" 2>&1
rc=$?
check "two frames only: exit 1" '[ $rc -eq 1 ] && grep -q "three are needed" "$TMP/o3.txt"'
mkdir -p "$TMP/same"
for i in 1 2 3; do cp "$DIR/view1.pgm" "$TMP/same/view$i.pgm"; done
printf 'sequence,timestamp_ns,file\n0,0,view1.pgm\n1,1,view2.pgm\n2,2,view3.pgm\n' > "$TMP/same/manifest.csv"
"$BIN" "$TMP/same" --camera 500,500,319.5,239.5 > "$TMP/o4.txt" 2>&1
rc=$?
check "three identical frames (no baseline): exit 1 with SFM_E_SINGULAR (-5)" \
    '[ $rc -eq 1 ] && grep -qF "(-5)" "$TMP/o4.txt"'
cat "$TMP/o4.txt"

# --calib: the scene's camera from an OpenCV FileStorage file gives the same
# figures as --camera; a file for another image size, or a broken one, is
# refused before any pose is printed.
calib() { # file, width, height
    printf '%%YAML:1.0\n---\nimage_width: %d\nimage_height: %d\ncamera_matrix: !!opencv-matrix\n   rows: 3\n   cols: 3\n   dt: d\n   data: [ 500., 0., 319.5, 0., 500., 239.5, 0., 0., 1. ]\ndistortion_coefficients: !!opencv-matrix\n   rows: 5\n   cols: 1\n   dt: d\n   data: [ 0., 0., 0., 0., 0. ]\n' "$2" "$3" > "$1"
}
calib "$TMP/cam.yaml" 640 480
"$BIN" "$DIR" --calib "$TMP/cam.yaml" --gt "$DIR/ground_truth.txt" 2>&1 | grep -v " ms" | grep -v "^  camera " > "$TMP/c1.txt"
"$BIN" "$DIR" --camera 500,500,319.5,239.5 --gt "$DIR/ground_truth.txt" 2>&1 | grep -v " ms" | grep -v "^  camera " > "$TMP/c2.txt"
check "--calib FILE gives the figures of --camera" 'grep -q "rotation error" "$TMP/c1.txt" && cmp -s "$TMP/c1.txt" "$TMP/c2.txt"'
calib "$TMP/cam2x.yaml" 1280 960
"$BIN" "$DIR" --calib "$TMP/cam2x.yaml" > "$TMP/o5.txt" 2>&1
rc=$?
check "--calib for another image size: exit 1, no poses" '[ $rc -eq 1 ] && grep -q "1280x960" "$TMP/o5.txt" && ! grep -q "poses" "$TMP/o5.txt"'
printf 'camera_matrix:\n  rows: 3\n  cols: 3\n  data: [500, 0, 319.5, 0, 500]\n' > "$TMP/bad.yaml"
"$BIN" "$DIR" --calib "$TMP/bad.yaml" > "$TMP/o6.txt" 2>&1
rc=$?
check "--calib with a malformed field: exit 2 naming the file and field" \
    '[ $rc -eq 2 ] && grep -q "bad.yaml: field .camera_matrix." "$TMP/o6.txt"'
cat "$TMP/o6.txt"

echo "test-demo: $pass passed, $fail failed"
[ $fail -eq 0 ]
