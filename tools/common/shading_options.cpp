// The shading options' registration (shading_options.hpp).
#include "common/shading_options.hpp"

#include "common/option_table.hpp"

#include <utility>
#include <vector>

namespace shprt::tools {

void add_shading_options(CLI::App& app, ShadingChoice& choice, unsigned extra,
                         const std::string& exposure_help, const std::string& direct_help) {
    std::vector<std::string> leave_out;
    if (!(extra & kCoeffsOption)) leave_out.push_back("shading_coeffs");
    if (!(extra & kSunSamplesOption)) leave_out.push_back("sun_samples");
    add_table_options(app, shading_option_table(), choice.params, leave_out);
    app.get_option("--exposure")->description(exposure_help);
    app.get_option("--direct")->description(direct_help);
    std::vector<std::string> named_leave_out;
    for (const auto& [flag, name] : {std::pair{kDeprecatedCoeffsOption, "coeffs"},
                                     {kAlbedoOption, "albedo"},
                                     {kViewOption, "view"},
                                     {kEyeOption, "eye"}})
        if (!(extra & flag)) named_leave_out.push_back(name);
    add_table_options(app, shading_choice_table(), choice, named_leave_out);
}

}  // namespace shprt::tools
