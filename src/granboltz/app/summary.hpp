#pragma once
// The one line `granboltz run` prints when a run has succeeded: where its output is, how long
// it took, and the values a user looks at first.
#include <string>

namespace granboltz {

/// "wrote PATH in S s: steady T = m ± ci, a2 = m ± ci" read back from the written output: the
/// steady values of the temperature, a2, theta and the TV06 ratios where the output has them, else
/// the last row's temperature. Never throws: an output it cannot read is named without values.
std::string run_summary(const std::string& path, double seconds);

}  // namespace granboltz
