// Names -> factories, each with a line of help: the function list behind
// every kind rcfd lets users choose by name (operators for -pipeline, carry
// kinds for -carry_type).  Like PETSc's PetscFunctionList, but owned by an
// object instead of being global, so two programs in one process do not see
// each other's additions.
#pragma once

#include <map>
#include <stdexcept>
#include <string>
#include <utility>

namespace rcfd {

template <typename Factory> class NamedFactories {
public:
  /// Adds or replaces `name`.  Throws std::invalid_argument unless the name is one word.
  void add(const std::string &name, Factory factory, const std::string &help) {
    if (name.empty() || name.find_first_of(", \t") != std::string::npos)
      throw std::invalid_argument("name '" + name + "' must be one word");
    entries[name] = {std::move(factory), help};
  }
  bool has(const std::string &name) const { return entries.count(name) > 0; }
  /// The factory registered as `name`.  Throws std::invalid_argument with
  /// "<option>: unknown <what> '<name>'; known <what>s: a, b" otherwise.
  const Factory &find(const std::string &name, const std::string &option,
                      const std::string &what) const {
    const auto it = entries.find(name);
    if (it == entries.end())
      throw std::invalid_argument(option + ": unknown " + what + " '" + name + "'; known " + what +
                                  "s: " + listing());
    return it->second.first;
  }
  /// The line of help given with `name` (empty if unknown).
  std::string help(const std::string &name) const {
    const auto it = entries.find(name);
    return it == entries.end() ? std::string() : it->second.second;
  }
  /// The names, comma-separated, in alphabetical order.
  std::string listing() const {
    std::string out;
    for (const auto &entry : entries) out += (out.empty() ? "" : ", ") + entry.first;
    return out;
  }

private:
  std::map<std::string, std::pair<Factory, std::string>> entries;
};

} // namespace rcfd
