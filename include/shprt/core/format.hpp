// Numbers for people, as the command line's progress and summaries print them.
#pragma once

#include <string>

namespace shprt {

// Three significant digits and an SI prefix: "51.2 M", "980", "1.00 k" (999.6 rounds up into the
// next prefix), "3.00", "-2.50 k"; prefixes up to P.
std::string format_si(double value);

// "0.35 s", "4.2 s", then m:ss from a minute on ("1:05", whole seconds rounded up) and h:mm:ss
// from an hour on; "?" for a negative or non-finite time.
std::string format_duration(double seconds);

// A fraction as a percentage to two significant digits, never in exponent form: "100" (1.0),
// "68", "7.8", "0.71", "0.0012"; "< 0.001" below that, "?" for a negative or non-finite one.
// The caller adds the " %".
std::string format_percent(double fraction);

}  // namespace shprt
