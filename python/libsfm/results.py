"""The result type every robust estimator returns."""
import numpy as np

from ._ffi import ffi, lib

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
      degenerate     bool, the model is a partial answer (see degeneracy)
      degeneracy     str: "" when not degenerate, else "pure_rotation" (R
                     without t), "low_parallax" (R determined, the direction
                     of t not), "planar" (a dominant plane: a relative pose
                     may be the twin of the true one, F rests on the few
                     points off the plane); a support that does not
                     determine the model at all raises SfmError instead

    and, when this build's C library reports them, polish_rounds,
    inner_runs, stop_share, samples_needed (the stopping rule's share and
    the samples it asked for) and covariance ((6, 6) of the pose, rows (w,
    t), w the rotation increment in radians; None for F, H and T).

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
           "polished", "score", "seed", "stop_reason", "flags", "degenerate", "degeneracy",
           "polish_rounds", "inner_runs", "stop_share", "samples_needed", "covariance")


_STATS_FIELDS = {name for name, _ in ffi.typeof("sfm_ransac_stats").fields}

#: Flag bits naming a partial answer, in order of precedence. A bit this
#: build's headers do not define is skipped.
_DEGENERACY_FLAGS = (("SFM_RANSAC_FLAG_PURE_ROTATION", "pure_rotation"),
                     ("SFM_RANSAC_FLAG_LOW_PARALLAX", "low_parallax"),
                     ("SFM_RANSAC_FLAG_PLANAR", "planar"),
                     ("SFM_RANSAC_FLAG_DEGENSAC", "planar"))

#: Run diagnostics exported when the C stats carry them: name -> type.
_OPTIONAL_STATS = (("polish_rounds", int), ("inner_runs", int), ("stop_share", float),
                   ("samples_needed", float))


def degeneracy_name(flags):
    """The degeneracy named by SFM_RANSAC_FLAG_* bits ("" when none)."""
    for const, name in _DEGENERACY_FLAGS:
        bit = getattr(lib, const, None)
        if bit is not None and flags & bit:
            return name
    return ""


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
               flags=int(st.flags))
    name = degeneracy_name(int(st.flags))
    r.update(degenerate=bool(name), degeneracy=name)
    for field, kind in _OPTIONAL_STATS:
        if field in _STATS_FIELDS:
            r[field] = kind(getattr(st, field))
    if "cov_dim" in _STATS_FIELDS:
        r["covariance"] = (np.array(list(st.covariance)).reshape(6, 6) if st.cov_dim == 6 else None)
    r.update(model)
    return r
