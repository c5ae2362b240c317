#include "cli/argument_check.hpp"

#include "base/input_file.hpp"

#include <cctype>
#include <cerrno>
#include <cstdlib>
#include <cstring>
#include <fstream>

namespace rcfd::cli {
namespace {

bool endsWith(const std::string &s, const std::string &tail) {
  return s.size() >= tail.size() && s.compare(s.size() - tail.size(), tail.size(), tail) == 0;
}

// One line of a flat YAML mapping; returns why it is not, or "".
std::string yamlLineProblem(const std::string &raw) {
  std::string line = raw;
  if (!line.empty() && line.back() == '\r') line.pop_back();
  const std::size_t indent = line.find_first_not_of(' ');
  if (indent == std::string::npos) return "";
  if (line[indent] == '\t' || line.find_first_of('\t') < line.find_first_not_of(" \t"))
    return "is indented with a tab (YAML allows spaces only)";
  if (line[indent] == '#') return "";
  if (line.compare(indent, 2, "- ") == 0 || line.compare(indent, 3, "---") == 0) return "";
  const std::size_t colon = line.find(':', indent);
  if (colon == std::string::npos) return "is not 'name: value'";
  const std::string key = line.substr(indent, colon - indent);
  if (key.empty()) return "has no name before ':'";
  for (char c : key)
    if (!std::isalnum(static_cast<unsigned char>(c)) && c != '_' && c != '-')
      return "has '" + key + "' as a name (letters, digits, _ and - only)";
  if (colon + 1 < line.size() && line[colon + 1] != ' ') return "needs a space after ':'";
  std::string value = line.substr(colon + 1);
  const std::size_t hash = value.find(" #");
  if (hash != std::string::npos) value.erase(hash);
  const std::size_t start = value.find_first_not_of(' ');
  if (start != std::string::npos && (value[start] == '"' || value[start] == '\'')) {
    const char quote = value[start];
    const std::size_t end = value.find_last_not_of(' ');
    if (end == start || value[end] != quote) return "opens a quote it does not close";
  }
  return "";
}

} // namespace

bool isOptionName(const std::string &word) {
  if (word.size() < 2 || word[0] != '-') return false;
  char *end = nullptr;
  errno = 0;
  std::strtod(word.c_str(), &end);
  return !(end && *end == '\0'); // "-5", "-1e-3", "-inf" are values
}

std::string strayArgument(int argc, char **argv, int first) {
  bool valueAllowed = false; // the previous word was an option name
  for (int i = first; i < argc; ++i) {
    const std::string word = argv[i];
    if (isOptionName(word)) {
      valueAllowed = true;
      continue;
    }
    if (!valueAllowed) return word;
    valueAllowed = false;
  }
  return "";
}

std::string checkOptionsFiles(int argc, char **argv) {
  for (int i = 1; i + 1 < argc; ++i) {
    if (std::strcmp(argv[i], "-options_file") != 0 && std::strcmp(argv[i], "-options_file_yaml") != 0)
      continue;
    const std::string path = argv[i + 1];
    if (const std::string problem = notRegularFile(path); !problem.empty()) return "-options_file: " + problem;
    std::ifstream in(path);
    if (!in) return "-options_file '" + path + "' cannot be read: " + std::strerror(errno);
    if (!endsWith(path, ".yaml") && !endsWith(path, ".yml") && std::strcmp(argv[i], "-options_file_yaml") != 0)
      continue;
    std::string line;
    for (int number = 1; std::getline(in, line); ++number) {
      const std::string problem = yamlLineProblem(line);
      if (!problem.empty())
        return "-options_file '" + path + "' line " + std::to_string(number) + " " + problem +
               " (rcfd reads a YAML mapping of option names to values)";
    }
  }
  return "";
}

} // namespace rcfd::cli
