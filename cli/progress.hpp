#pragma once
// A one-line progress indicator for long runs, shown only when standard
// error is a terminal (so logs and pipes stay clean).

#include <sage/sampling/grid.hpp>

#include <string>

namespace sage::cli {

/// A Progress callback that draws "label  42%" in place on a terminal, and
/// does nothing otherwise.
Progress terminal_progress(const std::string& label);

}  // namespace sage::cli
