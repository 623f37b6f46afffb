"""The result type every robust estimator returns."""
from ._ffi import lib

__all__ = ["Result"]

STOP_REASONS = {lib.SFM_RANSAC_STOP_CONFIDENCE: "confidence",
                lib.SFM_RANSAC_STOP_MAX_ITERATIONS: "max_iterations",
                lib.SFM_RANSAC_STOP_TIME: "time"}


class Result(dict):
    """What an estimator returns: a dict whose entries are also attributes
    (r["R"] is r.R).

    Entries shared by every estimator (types fixed):

      inliers        (n,) bool: the returned model's inliers
      num_inliers    int, always inliers.sum()
      iterations     int, samples drawn
      models         int, models verified
      sprt_rejected  int, models dropped early (SPRT or the bail-out test)
      lo_runs        int, local optimisations run
      polished       bool, the final polish was kept
      score          float, MSAC cost of the model (pixels squared)
      seed           int, the seed used (in [0, 2**64))
      stop_reason    str: "confidence", "max_iterations" or "time"
      flags          int, raw SFM_RANSAC_FLAG_* bits
      degenerate     bool, the inliers do not determine the model
      degeneracy     str, why: "" when not degenerate, else one of
                     "pure_rotation", "planar", "collinear", "clustered",
                     "low_parallax", "no_support"

    plus the model entries each estimator lists (R, t, E, F, H, T, P, ...).
    """

    def __getattr__(self, name):
        try:
            return self[name]
        except KeyError:
            raise AttributeError(name) from None

    def __dir__(self):
        return list(self.keys()) + list(super().__dir__())

    def __repr__(self):
        model = ", ".join(k for k in self if k not in _COMMON)
        return "Result(%d of %d inliers, %d iterations, stop_reason=%r%s; %s)" % (
            self["num_inliers"], len(self["inliers"]), self["iterations"], self["stop_reason"],
            ", degenerate: %s" % self["degeneracy"] if self.get("degenerate") else "", model)


_COMMON = ("inliers", "num_inliers", "iterations", "models", "sprt_rejected", "lo_runs",
           "polished", "score", "seed", "stop_reason", "flags", "degenerate", "degeneracy")


def ransac_result(st, mask, where, **model):
    """A Result from an sfm_ransac_stats and the uint8 inlier mask the C call
    wrote. The C count must be the mask's: a disagreement is a library bug,
    raised rather than returned."""
    inliers = mask.astype(bool)
    count = int(inliers.sum())
    if int(st.num_inliers) != count:
        raise AssertionError("%s: stats.num_inliers %d but the mask holds %d inliers"
                             % (where, int(st.num_inliers), count))
    r = Result(inliers=inliers, num_inliers=count, iterations=int(st.iterations),
               models=int(st.models), sprt_rejected=int(st.sprt_rejected),
               lo_runs=int(st.lo_runs), polished=bool(st.polished), score=float(st.score),
               seed=int(st.seed),
               stop_reason=STOP_REASONS.get(int(st.stop_reason), "unknown (%d)" % int(st.stop_reason)),
               flags=int(st.flags), degenerate=False, degeneracy="")
    r.update(model)
    return r
