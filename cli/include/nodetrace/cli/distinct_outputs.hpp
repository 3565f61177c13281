// Two outputs of one run in one file overwrite each other (the last one
// renamed into place wins), whether they are named by one string or by two
// (s.din and ./s.din, a link and its target): every front end refuses
// them before any work, by the file each name reaches, not by its spelling.
#pragma once

#include <string>
#include <vector>

namespace nodetrace::cli {

// One output of a command: the option that names it ("-o", "--per-level")
// and the path as given ("-": standard output).
struct NamedOutput {
  std::string option;
  std::string path;
};

// Whether `a` and `b` reach one file: device and inode where the file
// exists (standard output's for "-"), else the path resolved (symbolic links
// followed, "." and ".." removed). A character device (/dev/null, a
// terminal) takes any number of outputs and is never "one file".
bool same_output_file(const std::string& a, const std::string& b);

// Throws UsageError naming both options (and both paths where they are
// spelled differently) for the first two `outputs` that reach one file.
// Empty paths are skipped (no output).
void check_distinct_outputs(const std::vector<NamedOutput>& outputs);

}  // namespace nodetrace::cli
