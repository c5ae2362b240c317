// The ensemble summary (rcfd run -ensemble N): mean and sample standard
// deviation of every column over the members' cog.csv, exactly as written;
// members that do not match are refused naming the file.
#include "analysis/ensemble.hpp"
#include "check.hpp"

#include <filesystem>
#include <fstream>
#include <sstream>
#include <stdexcept>
#include <string>

using namespace rcfd;

namespace {

std::string write(const std::filesystem::path &dir, const std::string &name, const std::string &text) {
  const std::string path = (dir / name).string();
  std::ofstream(path) << text;
  return path;
}

std::string slurp(const std::string &path) {
  std::ifstream in(path);
  std::stringstream s;
  s << in.rdbuf();
  return s.str();
}

bool throwsWith(const std::vector<std::string> &csvs, const std::string &out, const std::string &text) {
  try {
    writeEnsembleSummary(csvs, out);
  } catch (const std::runtime_error &e) {
    return std::string(e.what()).find(text) != std::string::npos;
  }
  return false;
}

} // namespace

int main() {
  const auto dir = std::filesystem::temp_directory_path() / "rcfd_test_ensemble";
  std::filesystem::remove_all(dir);
  std::filesystem::create_directories(dir);
  // Three members; the time column is the same, z has mean 2 and sd 1 at t = 0,
  // mean 1/3 and sd sqrt(1/3) at t = 0.5, written with 10 digits (a comment
  // line and blanks are skipped, an empty field is a gap).
  const std::string a = write(dir, "a.csv", "time_s,z_m,dz_m\n0,1,0.25\n0.5,1,\n");
  const std::string b = write(dir, "b.csv", "# a comment\ntime_s,z_m,dz_m\n0,2,0.25\n0.5,0,\n");
  const std::string c = write(dir, "c.csv", "time_s, z_m, dz_m\n\n0,3,0.25\n0.5,0,\n");
  const std::string out = (dir / "ensemble.csv").string();
  writeEnsembleSummary({a, b, c}, out);
  RCFD_CHECK(slurp(out) == "# mean and sample standard deviation over 3 ensemble members\n"
                           "time_s,z_m_mean,z_m_std,dz_m_mean,dz_m_std\n"
                           "0,2,1,0.25,0\n"
                           "0.5,0.3333333333,0.5773502692,nan,nan\n");
  RCFD_CHECK(!std::filesystem::exists(out + ".tmp"));
  // One member: its values and zero spread.
  writeEnsembleSummary({a}, out);
  RCFD_CHECK(slurp(out).find("0.5,1,0,nan,0\n") != std::string::npos);

  const std::string shorter = write(dir, "short.csv", "time_s,z_m,dz_m\n0,1,0\n");
  const std::string renamed = write(dir, "renamed.csv", "time_s,z,dz_m\n0,1,0\n0.5,1,0\n");
  const std::string words = write(dir, "words.csv", "time_s,z_m,dz_m\n0,one,0\n0.5,1,0\n");
  RCFD_CHECK(throwsWith({a, shorter}, out, "ensemble member '" + shorter + "' does not have the rows"));
  RCFD_CHECK(throwsWith({a, renamed}, out, "ensemble member '" + renamed + "' does not have the rows"));
  RCFD_CHECK(throwsWith({a, words}, out, "'" + words + "', line 2, column 'z_m': expected a number, found 'one'"));
  RCFD_CHECK(throwsWith({a, (dir / "none.csv").string()}, out, "cannot open the ensemble member"));
  RCFD_CHECK(throwsWith({}, out, "at least one member"));
  RCFD_CHECK(throwsWith({a}, (dir / "no-such-dir" / "e.csv").string(), "cannot write"));
  std::filesystem::remove_all(dir);
  return RCFD_TEST_RESULT();
}
