#include "cli/argument_check.hpp"

#include "base/input_file.hpp"

#include <cctype>
#include <cerrno>
#include <cstdlib>
#include <cstring>
#include <fstream>
#include <map>
#include <vector>

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

// The option names of a YAML mapping's keys, nested as PETSc reads them (`drift:` with
// `kd: 5e3` indented below it is -drift_kd), to find a key given twice: YAML forbids
// it, and PETSc would silently take the last value.
class YamlKeys {
public:
  /// The line (1-based) that gave `line`'s option name before, or 0; `name` is set to it.
  int repeated(const std::string &raw, int number, std::string &name) {
    std::string line = raw;
    if (!line.empty() && line.back() == '\r') line.pop_back();
    const std::size_t indent = line.find_first_not_of(' ');
    if (indent == std::string::npos || line[indent] == '#' || line.compare(indent, 2, "- ") == 0)
      return 0;
    if (line.compare(indent, 3, "---") == 0) { // a new document
      parents.clear();
      seen.clear();
      return 0;
    }
    const std::size_t colon = line.find(':', indent);
    if (colon == std::string::npos) return 0;
    while (!parents.empty() && parents.back().indent >= indent) parents.pop_back();
    name.clear();
    for (const auto &p : parents) name += p.key + "_";
    name += line.substr(indent, colon - indent);
    std::string value = line.substr(colon + 1);
    const std::size_t hash = value.find(" #");
    if (hash != std::string::npos) value.erase(hash);
    if (value.find_first_not_of(' ') == std::string::npos) // `name:` may open a nested mapping
      parents.push_back({indent, line.substr(indent, colon - indent)});
    const auto [at, inserted] = seen.emplace(name, number);
    return inserted ? 0 : at->second;
  }

private:
  struct Parent {
    std::size_t indent;
    std::string key;
  };
  std::vector<Parent> parents;
  std::map<std::string, int> seen;
};

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
    std::string line, name;
    YamlKeys keys;
    for (int number = 1; std::getline(in, line); ++number) {
      const std::string problem = yamlLineProblem(line);
      if (!problem.empty())
        return "-options_file '" + path + "' line " + std::to_string(number) + " " + problem +
               " (rcfd reads a YAML mapping of option names to values)";
      if (const int first = keys.repeated(line, number, name))
        return "-options_file '" + path + "' gives '" + name + "' on line " + std::to_string(first) +
               " and again on line " + std::to_string(number) +
               " (YAML forbids a key twice, and which value would count is not clear: keep one)";
    }
  }
  return "";
}

} // namespace rcfd::cli
