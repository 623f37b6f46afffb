/*
 * The anchor of bench/uncal_bench.c: BoofCV 1.2.2's own uncalibrated
 * three-view pipeline (ThreeViewEstimateMetricScene: trifocal RANSAC with
 * self-calibration inside, metric bundle adjustment, pruning) on the same
 * Herz-Jesu-P8 match triplets, at its default configuration. Pixels are
 * shifted by the image centre first, as its process() requires.
 *
 * Prints per triplet the status, the focal length of its shared camera and
 * the wall-clock time of process(); then the median and mean time, the
 * count answered, the count within 5 % of the ground-truth focal length and
 * the count answered but outside it. A first pass over the first WARM
 * triplets is run and discarded so that the timing is of compiled code, as
 * a long-running process would see it.
 *
 * Usage: java -cp CLASSPATH UncalBoofcv DIR [WARM]
 */
import boofcv.alg.structure.ThreeViewEstimateMetricScene;
import boofcv.struct.geo.AssociatedTriple;
import georegression.struct.point.Point2D_F64;

import java.io.BufferedReader;
import java.io.FileReader;
import java.io.IOException;
import java.util.ArrayList;
import java.util.Arrays;
import java.util.List;

public class UncalBoofcv {
	static final int W = 3072, H = 2048;
	static final double F_TRUE = 2759.48; // herzjesu-p8/K.txt

	static List<String[]> index( String dir ) throws IOException {
		List<String[]> out = new ArrayList<>();
		try (var r = new BufferedReader(new FileReader(dir + "/triplets_index.txt"))) {
			for (String l; (l = r.readLine()) != null; ) {
				if (l.startsWith("#")) continue;
				String[] t = l.trim().split("\\s+");
				if (t.length >= 3) out.add(t);
			}
		}
		return out;
	}

	static List<AssociatedTriple> triples( String path ) throws IOException {
		List<AssociatedTriple> out = new ArrayList<>();
		try (var r = new BufferedReader(new FileReader(path))) {
			for (String l; (l = r.readLine()) != null; ) {
				if (l.startsWith("#")) continue;
				String[] t = l.trim().split("\\s+");
				if (t.length != 6) continue;
				double[] v = new double[6];
				for (int k = 0; k < 6; k++) v[k] = Double.parseDouble(t[k]);
				out.add(new AssociatedTriple(
						new Point2D_F64(v[0] - W/2, v[1] - H/2),
						new Point2D_F64(v[2] - W/2, v[3] - H/2),
						new Point2D_F64(v[4] - W/2, v[5] - H/2)));
			}
		}
		return out;
	}

	/** Runs the pipeline once: the focal length, or NaN when process() fails or throws. */
	static double run( List<AssociatedTriple> obs ) {
		var alg = new ThreeViewEstimateMetricScene();
		alg.initialize(W, H);
		try {
			if (!alg.process(obs)) return Double.NaN;
		} catch (RuntimeException e) {
			return Double.NaN;
		}
		return alg.listPinhole.get(0).fx;
	}

	public static void main( String[] args ) throws IOException {
		String dir = args.length > 0 ? args[0] : "../shared/data/herzjesu-p8/triplets";
		int warm = args.length > 1 ? Integer.parseInt(args[1]) : 5;
		List<String[]> idx = index(dir);
		for (int i = 0; i < Math.min(warm, idx.size()); i++) {
			String[] t = idx.get(i);
			run(triples(dir + "/triplet_" + t[0] + "_" + t[1] + "_" + t[2] + ".txt"));
		}
		double[] ms = new double[idx.size()];
		int ok = 0, within = 0, wrong = 0;
		for (int i = 0; i < idx.size(); i++) {
			String[] t = idx.get(i);
			List<AssociatedTriple> obs = triples(dir + "/triplet_" + t[0] + "_" + t[1] + "_" + t[2] + ".txt");
			long t0 = System.nanoTime();
			double f = run(obs);
			ms[i] = (System.nanoTime() - t0)*1e-6;
			boolean answered = !Double.isNaN(f);
			boolean good = answered && Math.abs(f/F_TRUE - 1) <= 0.05;
			ok += answered ? 1 : 0;
			within += good ? 1 : 0;
			wrong += answered && !good ? 1 : 0;
			System.out.printf("%s %s %s  n %4d  %s  f %7.1f  %8.1f ms%n", t[0], t[1], t[2], obs.size(),
					answered ? "ok  " : "fail", answered ? f : 0.0, ms[i]);
		}
		double[] s = ms.clone();
		Arrays.sort(s);
		double sum = 0;
		for (double v : ms) sum += v;
		System.out.printf("BoofCV 1.2.2 ThreeViewEstimateMetricScene, %d Herz-Jesu-P8 triplets: %d answered, " +
				"%d within 5 %% of f, %d answered outside; median %.1f ms per triplet, mean %.1f ms%n",
				ms.length, ok, within, wrong, s[ms.length/2], sum/ms.length);
	}
}
