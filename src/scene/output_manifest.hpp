#pragma once
// The files a run or a sweep wrote into its output directory, listed in a
// hidden manifest there, so that the next one into the same directory
// removes them all before it starts (plots included) and nothing of an
// earlier run can pass for its own.

#include <string>
#include <vector>

namespace lagrangian::scene::detail {

/// Removes `fixed` (plain file names) with their ".partial" files, and every
/// file the directory's manifest lists, then the manifest. Only plain file
/// names in `dir` are touched.
void remove_listed_outputs(const std::string& dir, const std::vector<std::string>& fixed);

/// Writes the manifest of those `files` (paths) that lie directly in `dir`.
void write_output_manifest(const std::string& dir, const std::vector<std::string>& files);

}  // namespace lagrangian::scene::detail
