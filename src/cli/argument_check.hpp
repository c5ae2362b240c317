// Checks of the command line made before PETSc sees it: PETSc silently
// ignores a word that is neither an option nor an option's value (an unquoted
// glob `-dumps dump/*.gz` then builds from the first file only), and prints a
// long dump without file or line for a YAML options file it cannot parse.
#pragma once

#include <string>

namespace rcfd::cli {

/// True when `word` names an option ("-t_end"), not a value such as "-5" or "-1e-3".
bool isOptionName(const std::string &word);

/// The first word of argv[first..argc) that is neither an option nor the value
/// right after an option; empty when there is none.
std::string strayArgument(int argc, char **argv, int first);

/// Checks every -options_file of argv: the file can be read and, for a YAML file
/// (.yaml or .yml), every line is blank, a comment, `name: value`, `name:` or a list
/// item, indented with spaces.  Returns one sentence naming the file and line, or "".
std::string checkOptionsFiles(int argc, char **argv);

} // namespace rcfd::cli
