#!/bin/sh
# libsfm's uncalibrated three-view pipeline beside its anchor, BoofCV 1.2.2's
# ThreeViewEstimateMetricScene, on the Herz-Jesu-P8 match triplets, in one run
# on this machine: libsfm (bench/uncal_bench), BoofCV
# (bench/boofcv/UncalBoofcv.java), libsfm again, each pinned to one core when
# taskset exists. Prints both summaries and the ratio of the median times
# (libsfm's two runs averaged). BoofCV is resolved by Maven from
# bench/boofcv/pom.xml into the local repository; without java, javac or mvn,
# or when it cannot be resolved, the bench says SKIP.
# Usage: uncal_vs_boofcv.sh path/to/uncal_bench BUILD_DIR [DIR]
set -eu
bin=$1
build=$2
dir=${3:-../shared/data/herzjesu-p8/triplets}
here=$(dirname "$0")
for t in java javac mvn; do
    command -v $t > /dev/null || { echo "SKIP: $t not found"; exit 0; }
done
[ -f "$dir/triplets_index.txt" ] || { echo "SKIP: $dir/triplets_index.txt not found"; exit 0; }
out=$build/bench/boofcv
mkdir -p "$out"
if [ ! -s "$out/cp.txt" ]; then
    mvn -q -f "$here/boofcv/pom.xml" dependency:build-classpath -Dmdep.outputFile="$(pwd)/$out/cp.txt" \
        > "$out/mvn.log" 2>&1 || { echo "SKIP: BoofCV 1.2.2 not resolved (see $out/mvn.log)"; rm -f "$out/cp.txt"; exit 0; }
fi
cp=$(cat "$out/cp.txt")
javac -cp "$cp" -d "$out" "$here/boofcv/UncalBoofcv.java"
pin=""
command -v taskset > /dev/null && pin="taskset -c 0"
median() { sed -n 's/.*median \([0-9.]*\) ms per triplet.*/\1/p' "$1" | head -1; }
$pin "$bin" "$dir" > "$out/libsfm1.txt"
$pin java -XX:ActiveProcessorCount=1 -cp "$cp:$out" UncalBoofcv "$dir" > "$out/boofcv.txt"
$pin "$bin" "$dir" > "$out/libsfm2.txt"
tail -2 "$out/libsfm1.txt"
tail -1 "$out/boofcv.txt"
tail -2 "$out/libsfm2.txt"
a=$(median "$out/libsfm1.txt")
b=$(median "$out/boofcv.txt")
c=$(median "$out/libsfm2.txt")
awk -v a="$a" -v b="$b" -v c="$c" 'BEGIN {
    m = (a + c) / 2
    printf "median per triplet: libsfm %.1f ms (runs %.1f, %.1f), BoofCV %.1f ms: ratio %.3f (BoofCV %.1f times slower)\n", m, a, c, b, m / b, b / m
}'
echo "per-triplet lines: $out/libsfm1.txt, $out/boofcv.txt, $out/libsfm2.txt"
