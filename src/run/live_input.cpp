// The live file (docs/live.md): read on rank 0 from where the last look
// stopped, complete lines only (a writer may be half-way through a line),
// broadcast to every rank.
//
// Waiting polls the file with a sleep rather than inotify: plant logs often
// sit on network shares, where inotify sees no remote writes, a stat and a
// read of the appended bytes every -live_poll seconds (0.2 s) cost nothing
// beside the run, and the delay they add is a fraction of the process time
// a row stands for.  Every rank sleeps between looks (MPI's blocking
// collectives would spin the ranks that wait for rank 0).
#include "run/live_input.hpp"
#include "rcfd/fractions.hpp"
#include "rcfd/granulation.hpp"
#include "run/find_operator.hpp"
#include "base/checked_options.hpp"
#include "base/petsc_compat.hpp"

#include <algorithm>
#include <cerrno>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <ctime>
#include <filesystem>
#include <fstream>
#include <sstream>

namespace rcfd {
namespace {

// Set by the handler, read by the run at its next look.  A signal handler can
// reach nothing but a flag of static storage: the one state outside objects.
volatile std::sig_atomic_t signalled = 0;
extern "C" void onSignal(int) { signalled = 1; }

std::string trim(const std::string &s) {
  const auto b = s.find_first_not_of(" \t\r");
  if (b == std::string::npos) return "";
  return s.substr(b, s.find_last_not_of(" \t\r") - b + 1);
}

std::vector<std::string> splitFields(const std::string &line) {
  std::vector<std::string> out;
  std::stringstream ss(line);
  std::string item;
  while (std::getline(ss, item, ',')) out.push_back(trim(item));
  if (!line.empty() && line.back() == ',') out.push_back("");
  return out;
}

const char *const kNames[LiveInput::NumQuantities] = {"u_sup",       "feed_rate",       "discharge_rate", "growth_rate",
                                                      "spray_rate", "gas_temperature", "feed_share_"};

} // namespace

LiveInput::~LiveInput() {
  if (handlersInstalled_) {
    sigaction(SIGINT, &previousInt_, nullptr);
    sigaction(SIGTERM, &previousTerm_, nullptr);
  }
}

PetscErrorCode LiveInput::setFromOptions(MPI_Comm comm) {
  char text[PETSC_MAX_PATH_LEN] = "";
  char policy[16] = "fail";
  PetscBool set = PETSC_FALSE, paced = PETSC_FALSE;
  PetscFunctionBeginUser;
  comm_ = comm;
  PetscOptionsBegin(comm, nullptr, "Live conditions (docs/live.md)", "rcfd");
  PetscCall(PetscOptionsString("-live", "CSV file of measured conditions the run follows as it grows (time_s, "
                               "u_sup, feed_rate, discharge_rate, growth_rate, spray_rate, gas_temperature, "
                               "feed_share_<fraction>)", "", text,
                               text, sizeof text, &set));
  if (set) path_ = text;
  PetscCall(PetscOptionsString("-live_on_bad_line", "A malformed line of the live file: fail (the run stops) or "
                               "skip (said on stderr)", "", policy, policy, sizeof policy, nullptr));
  text[0] = '\0';
  PetscCall(PetscOptionsString("-live_stop_file", "The live run ends when this file exists, once it has "
                               "followed the rows written before it", "", text, text, sizeof text, &set));
  if (set) stopFile_ = text;
  PetscCall(checkedReal(PetscOptionsObject, "-live_end", "Process time at which the live run ends [s] (default: "
                        "none, the stop file or a signal ends it)", &end_, {0.0, 1e15, false, true,
                        "a positive time in s"}));
  PetscCall(PetscOptionsBool("-live_pace", "Keep the live run at the wall clock (no faster than real time)", "",
                             paced, &paced, nullptr));
  PetscCall(checkedReal(PetscOptionsObject, "-live_poll", "Wall seconds between looks at the live file while "
                        "waiting", &poll_, {1e-3, 3600.0, true, true, "a time in [0.001, 3600] s"}));
  PetscOptionsEnd();
  paced_ = paced == PETSC_TRUE;
  const std::string p = policy;
  PetscCheck(p == "fail" || p == "skip", comm, PETSC_ERR_USER_INPUT,
             "-live_on_bad_line %s is not known; use fail (a malformed line stops the run) or skip", policy);
  failOnBadLine_ = p == "fail";
  PetscFunctionReturn(PETSC_SUCCESS);
}

std::string LiveInput::parseHeader(const std::string &line, const FractionSet &fractions) {
  const std::string file = option_ + " " + path_ + ": ";
  const std::vector<std::string> names = splitFields(line);
  std::string known = "time_s";
  for (int q = 0; q < FeedShare; ++q) known += std::string(", ") + kNames[q];
  known += ", feed_share_<fraction> (";
  for (int i = 0; i < fractions.size(); ++i) known += (i ? ", feed_share_" : "feed_share_") + fractions.label(i);
  known += ")";
  std::vector<int> share(fractions.size(), -1);
  int value = 0;
  for (std::size_t c = 0; c < names.size(); ++c) {
    const std::string &n = names[c];
    for (std::size_t d = 0; d < c; ++d)
      if (names[d] == n) return file + "the header names the column '" + n + "' twice";
    if (n == "time_s" || n == "time") {
      timeColumn_ = static_cast<int>(c);
      continue;
    }
    int q = -1;
    for (int k = 0; k < FeedShare; ++k)
      if (n == kNames[k]) q = k;
    int fraction = -1;
    for (int i = 0; i < fractions.size(); ++i)
      if (n == "feed_share_" + fractions.label(i)) fraction = i;
    if (q < 0 && fraction < 0)
      return file + "the column '" + n + "' is not a condition rcfd follows; the columns it knows are " + known;
    if (q >= 0) column_[q] = value++;
    else share[fraction] = value++;
  }
  if (timeColumn_ < 0) return file + "the header '" + line + "' has no time_s column";
  int given = 0;
  for (int c : share) given += c >= 0;
  if (given > 0 && given < fractions.size())
    return file + "the feed shares name " + std::to_string(given) + " of the " + std::to_string(fractions.size()) +
           " fractions; give feed_share_<label> for each (" + known.substr(known.find('(') + 1);
  if (given > 0) shareColumns_ = share;
  width_ = value;
  names_ = names;
  return "";
}

std::string LiveInput::parseRow(const std::string &line, long number, double previous,
                                std::vector<double> *row) const {
  char where[64];
  std::snprintf(where, sizeof where, " line %ld: ", number);
  const std::string at = option_ + " " + path_ + where;
  const std::vector<std::string> fields = splitFields(line);
  if (fields.size() != names_.size())
    return at + "expected " + std::to_string(names_.size()) + " comma-separated numbers (" + [&] {
      std::string h;
      for (const auto &n : names_) h += (h.empty() ? "" : ",") + n;
      return h;
    }() + "), got '" + line + "'";
  row->assign(width_ + 1, 0.0);
  int value = 0;
  for (std::size_t c = 0; c < fields.size(); ++c) {
    const char *s = fields[c].c_str();
    char *endp = nullptr;
    errno = 0;
    const double v = std::strtod(s, &endp);
    if (fields[c].empty() || *endp != '\0' || errno == ERANGE)
      return at + names_[c] + " '" + fields[c] + "' is not a number";
    if (!std::isfinite(v)) return at + names_[c] + " is " + fields[c] + "; expected a finite number";
    if (static_cast<int>(c) == timeColumn_) (*row)[0] = v;
    else (*row)[1 + value++] = v;
  }
  const double t = (*row)[0];
  char text[160];
  if (previous < 0 && t != 0.0) {
    std::snprintf(text, sizeof text, "the first row must be at time 0 s (the %s start), got %.9g s",
                  whole_ ? "forecast's" : "run's", t);
    return at + text;
  }
  // Rows closer than round-off could not be told apart by the run's clock.
  if (previous >= 0 && !(t > previous * (1.0 + 1e-9) && t > previous)) {
    std::snprintf(text, sizeof text, "time %.9g s is not after the previous row's %.9g s; times must increase", t,
                  previous);
    return at + text;
  }
  auto check = [&](int q, bool ok, const char *expected) -> std::string {
    if (ok) return "";
    std::snprintf(text, sizeof text, "%s %.9g is not %s", kNames[q], (*row)[1 + column_[q]], expected);
    return at + text;
  };
  std::string bad;
  if (column_[SuperficialVelocity] >= 0 && bad.empty())
    bad = check(SuperficialVelocity, (*row)[1 + column_[SuperficialVelocity]] > 0, "a positive velocity in m/s");
  for (int q : {FeedRate, DischargeRate, GrowthRate, SprayRate})
    if (column_[q] >= 0 && bad.empty()) bad = check(q, (*row)[1 + column_[q]] >= 0, "a rate >= 0 in kg/s");
  if (column_[GasTemperature] >= 0 && bad.empty())
    bad = check(GasTemperature, (*row)[1 + column_[GasTemperature]] > 0, "a positive temperature in K");
  if (!bad.empty()) return bad;
  if (!shareColumns_.empty()) {
    double sum = 0.0;
    bool valid = true;
    for (int c : shareColumns_) {
      valid = valid && (*row)[1 + c] >= 0;
      sum += (*row)[1 + c];
    }
    if (!valid || std::fabs(sum - 1.0) > 1e-6) {
      std::snprintf(text, sizeof text, "the feed shares sum to %.9g; expected shares >= 0 that sum to 1", sum);
      return at + text;
    }
  }
  return "";
}

std::string LiveInput::readNew(std::vector<double> *rows) {
  namespace fs = std::filesystem;
  std::error_code ec;
  const auto size = fs::file_size(path_, ec);
  if (ec) { // not there yet: the plant starts writing later; once read, it must stay
    if (offset_ == 0) return whole_ ? option_ + " " + path_ + ": cannot read the file (" + ec.message() + ")" : "";
    return option_ + " " + path_ + ": the file went away after " + std::to_string(offset_) + " bytes were read";
  }
  if (static_cast<long long>(size) < offset_)
    return option_ + " " + path_ + ": the file shrank to " + std::to_string(size) + " bytes after " +
           std::to_string(offset_) + " were read; it must only grow";
  if (static_cast<long long>(size) == offset_) return "";
  std::ifstream in(path_, std::ios::binary);
  in.seekg(offset_);
  std::string chunk(static_cast<std::size_t>(size) - static_cast<std::size_t>(offset_), '\0');
  in.read(chunk.data(), static_cast<std::streamsize>(chunk.size()));
  chunk.resize(static_cast<std::size_t>(in.gcount()));
  if (whole_ && !chunk.empty() && chunk.back() != '\n') chunk += '\n'; // complete: its last line too
  double previous = times_.empty() ? -1.0 : times_.back();
  std::size_t begin = 0;
  for (std::size_t nl; (nl = chunk.find('\n', begin)) != std::string::npos; begin = nl + 1) {
    offset_ += static_cast<long long>(nl + 1 - begin); // a line without its end waits for the rest
    ++lineNumber_;
    const std::string line = trim(chunk.substr(begin, nl - begin));
    if (line.empty() || line[0] == '#') continue;
    if (!headerRead_) {
      headerRead_ = true;
      header_ = line;
      const std::string why = parseHeader(line, *fractions_);
      if (!why.empty()) return why;
      continue;
    }
    std::vector<double> row;
    const std::string why = parseRow(line, lineNumber_, previous, &row);
    if (why.empty()) {
      rows->insert(rows->end(), row.begin(), row.end());
      previous = row[0];
    } else if (failOnBadLine_) {
      return whole_ ? why : why + " (-live_on_bad_line fail)";
    } else {
      ++skipped_;
      (void)PetscFPrintf(PETSC_COMM_SELF, stderr, "%s; skipped (-live_on_bad_line skip)\n", why.c_str());
    }
  }
  return "";
}

PetscErrorCode LiveInput::exchange(double) {
  PetscMPIInt rank;
  PetscFunctionBeginUser;
  PetscCallMPI(MPI_Comm_rank(comm_, &rank));
  int caught = signalled ? 1 : 0;
  PetscCallMPI(MPI_Allreduce(MPI_IN_PLACE, &caught, 1, MPI_INT, MPI_MAX, comm_));
  std::vector<double> rows;
  std::string why;
  const bool hadHeader = !names_.empty();
  long long head[4] = {0, 0, 0, 0}; // stop file seen, values of the new rows, error's length, header's length
  if (rank == 0) {
    // The stop file is looked at before the file is read: the rows written before it are followed.
    head[0] = !stopFile_.empty() && std::filesystem::exists(stopFile_);
    try {
      why = readNew(&rows);
    } catch (const std::exception &e) {
      why = option_ + " " + path_ + ": " + e.what();
    }
    head[1] = static_cast<long long>(rows.size());
    head[2] = static_cast<long long>(why.size());
    head[3] = hadHeader || header_.empty() ? 0 : static_cast<long long>(header_.size());
  }
  PetscCallMPI(MPI_Bcast(head, 4, MPI_LONG_LONG, 0, comm_));
  if (head[2] > 0) {
    why.resize(static_cast<std::size_t>(head[2]));
    PetscCallMPI(MPI_Bcast(why.data(), static_cast<int>(head[2]), MPI_CHAR, 0, comm_));
    SETERRQ(comm_, PETSC_ERR_USER_INPUT, "%s", why.c_str());
  }
  if (head[3] > 0) { // the other ranks learn the columns from the same header
    header_.resize(static_cast<std::size_t>(head[3]));
    PetscCallMPI(MPI_Bcast(header_.data(), static_cast<int>(head[3]), MPI_CHAR, 0, comm_));
    if (rank != 0) (void)parseHeader(header_, *fractions_);
  }
  rows.resize(static_cast<std::size_t>(head[1]));
  if (head[1] > 0) PetscCallMPI(MPI_Bcast(rows.data(), static_cast<int>(head[1]), MPI_DOUBLE, 0, comm_));
  for (std::size_t k = 0; k < rows.size(); k += width_ + 1) {
    times_.push_back(rows[k]);
    rows_.insert(rows_.end(), rows.begin() + static_cast<long>(k) + 1, rows.begin() + static_cast<long>(k + width_ + 1));
  }
  stopSeen_ = head[0] != 0;
  if (caught) ended_ = End::Signal;
  PetscFunctionReturn(PETSC_SUCCESS);
}

PetscErrorCode LiveInput::start(MPI_Comm comm, const FractionSet &fractions, bool quiet) {
  PetscFunctionBeginUser;
  comm_ = comm;
  fractions_ = &fractions;
  quiet_ = quiet;
  if (!handlersInstalled_) { // a stop by signal ends at a step, with a checkpoint
    struct sigaction action {};
    action.sa_handler = onSignal;
    sigemptyset(&action.sa_mask);
    sigaction(SIGINT, &action, &previousInt_);
    sigaction(SIGTERM, &action, &previousTerm_);
    handlersInstalled_ = true;
    signalled = 0;
  }
  End end = End::None;
  PetscCall(waitFor(0.0, &end, [&]() -> PetscErrorCode {
    if (!quiet_) PetscCall(PetscPrintf(comm_, "Waiting for the live file %s: its header and a row at time 0\n", path_.c_str()));
    return PETSC_SUCCESS;
  }));
  PetscCheck(!times_.empty(), comm, PETSC_ERR_USER_INPUT,
             "-live %s: the run was stopped (%s) before the file held its header and a row at time 0", path_.c_str(),
             end == End::Signal ? "a signal" : "the stop file");
  PetscFunctionReturn(PETSC_SUCCESS);
}

PetscErrorCode LiveInput::readWhole(MPI_Comm comm, const std::string &option, const std::string &file,
                                   const FractionSet &fractions) {
  PetscFunctionBeginUser;
  comm_ = comm;
  option_ = option;
  path_ = file;
  fractions_ = &fractions;
  whole_ = true;
  PetscCall(exchange(0.0));
  PetscCheck(!times_.empty(), comm, PETSC_ERR_USER_INPUT,
             "%s %s: the file holds no %s; expected a header (time_s and the conditions) and a row at time 0",
             option.c_str(), file.c_str(), names_.empty() ? "header" : "row");
  PetscFunctionReturn(PETSC_SUCCESS);
}

double LiveInput::at(Quantity q, double t, int i) const {
  const int c = q == FeedShare ? (shareColumns_.empty() ? -1 : shareColumns_[i]) : column_[q];
  if (c < 0 || times_.empty()) return std::numeric_limits<double>::quiet_NaN();
  const auto after = std::upper_bound(times_.begin(), times_.end(), t * (1.0 + 1e-12));
  const std::size_t k = after == times_.begin() ? 0 : static_cast<std::size_t>(after - times_.begin()) - 1;
  return rows_[k * width_ + c];
}

PetscErrorCode LiveInput::interrupted(End *end) {
  int caught = signalled ? 1 : 0;
  PetscFunctionBeginUser;
  PetscCallMPI(MPI_Allreduce(MPI_IN_PLACE, &caught, 1, MPI_INT, MPI_MAX, comm_));
  if (caught) ended_ = End::Signal;
  *end = ended_;
  PetscFunctionReturn(PETSC_SUCCESS);
}

void LiveInput::pace(double simulated) {
  if (!paced_) return;
  const double now = MPI_Wtime();
  if (paceWall_ < 0) {
    paceWall_ = now;
    paceSimulated_ = simulated;
    return;
  }
  const double ahead = (simulated - paceSimulated_) - (now - paceWall_);
  if (ahead > 1e-3) sleepSeconds(ahead);
}

void LiveInput::sleepSeconds(double seconds) {
  struct timespec ts;
  ts.tv_sec = static_cast<time_t>(seconds);
  ts.tv_nsec = static_cast<long>((seconds - static_cast<double>(ts.tv_sec)) * 1e9);
  while (nanosleep(&ts, &ts) == -1 && errno == EINTR && !signalled) {
  }
}

std::string granulatorColumnWithoutOperator(const LiveInput &in, const Pipeline &ops) {
  if ((in.has(LiveInput::FeedRate) || in.has(LiveInput::FeedShare)) && !findOperator<FeedOperator>(ops))
    return "the feed columns need the feed operator in -pipeline";
  if (in.has(LiveInput::DischargeRate) && !findOperator<DischargeOperator>(ops))
    return "the column discharge_rate needs the discharge operator in -pipeline";
  if (in.has(LiveInput::GrowthRate) && !findOperator<GrowthOperator>(ops))
    return "the column growth_rate needs the growth operator in -pipeline";
  return "";
}

void setGranulatorRates(const LiveInput &in, double t, const Pipeline &ops) {
  if (auto *feed = findOperator<FeedOperator>(ops)) {
    const bool rate = in.has(LiveInput::FeedRate), shares = in.has(LiveInput::FeedShare);
    if (rate || shares) {
      std::vector<double> w = feed->feedShares();
      if (shares)
        for (std::size_t i = 0; i < w.size(); ++i) w[i] = in.at(LiveInput::FeedShare, t, static_cast<int>(i));
      feed->setFeed(rate ? in.at(LiveInput::FeedRate, t) : feed->feedRate(), w);
    }
  }
  if (auto *discharge = findOperator<DischargeOperator>(ops))
    if (in.has(LiveInput::DischargeRate)) discharge->setRate(in.at(LiveInput::DischargeRate, t));
  if (auto *growth = findOperator<GrowthOperator>(ops))
    if (in.has(LiveInput::GrowthRate)) growth->setRate(in.at(LiveInput::GrowthRate, t), growth->transferFraction());
}

} // namespace rcfd
