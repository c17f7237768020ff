// Human-readable description of a .shprt file, for `shprt info`.
#include "io/shprt_metadata.hpp"
#include "shprt/io/shprt_file.hpp"

#include <fmt/format.h>

namespace shprt {

std::string describe_convergence(const InterreflectionInfo& ir) {
    if (ir.converge)
        return fmt::format("{}: last relative change {:.2g} {} tolerance {:.2g}",
                           ir.converged ? "converged" : "NOT converged", ir.last_change,
                           ir.converged ? "<" : ">=", ir.tolerance);
    if (ir.bounces == 0) return "the direct light only";
    // Issue 40: a fixed count's last change read as "not converged"; it is information.
    return fmt::format(
        "a fixed count, not tested for convergence; largest relative change by "
        "bounce {}: {:.2g}",
        ir.bounces, ir.last_change);
}

// The lines are the metadata field table's (shprt_metadata.cpp), in their summary order.
std::string shprt_summary(const ShprtFile& file) { return detail::summarise_metadata(file); }

}  // namespace shprt
