#include "sfm/sfm_common.h"

const char *sfm_status_str(int status)
{
    if (status >= 0)
        return "ok";
    switch (status) {
    case SFM_E_ARGUMENT: return "invalid argument";
    case SFM_E_NONFINITE: return "non-finite input";
    case SFM_E_WORKSPACE: return "workspace too small";
    case SFM_E_CAPACITY: return "capacity exceeded";
    case SFM_E_SINGULAR: return "singular or degenerate configuration";
    case SFM_E_NO_CONVERGENCE: return "no convergence";
    case SFM_E_IO: return "input/output error";
    case SFM_E_TIMEOUT: return "timeout";
    case SFM_E_UNSUPPORTED: return "unsupported";
    case SFM_E_DEVICE_LOST: return "device lost";
    case SFM_E_NO_DEVICE: return "no such device";
    case SFM_E_FORMAT: return "malformed data";
    case SFM_E_DEGENERATE: return "degenerate support: the inliers do not determine the model";
    case SFM_E_NO_MODEL: return "no model: support no better than random matches";
    default: return "unknown status";
    }
}

int sfm_version(void)
{
    return SFM_VERSION_MAJOR * 10000 + SFM_VERSION_MINOR * 100 + SFM_VERSION_PATCH;
}
