#pragma once
// Output files written whole or not at all. A run checks its output path
// before the work that fills it (a missing folder is found in a second,
// not after the solve), and writes into a temporary file beside it that is
// renamed over the path at the end: a failed or interrupted run never
// leaves a truncated file in place of the user's previous result.

#include <functional>
#include <string>

namespace sage::output {

/// Throws OutputError (vtk_writer.hpp) naming `path` when a file cannot be
/// made there: its folder does not exist or is not writable, or the path is
/// a folder. Leaves an existing file at `path` untouched.
void check_writable(const std::string& path);

/// Calls write(temporary) with a path beside `path`, then renames the file
/// over `path`. When `write` throws, the temporary file is removed and the
/// exception passes on; `path` is left as it was.
void write_atomically(const std::string& path, const std::function<void(const std::string& temporary)>& write);

}  // namespace sage::output
