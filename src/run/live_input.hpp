// rcfd run -live FILE (docs/live.md): the operating conditions a plant or a
// lab appends to a CSV file while the run follows them.  Rank 0 reads the
// file and broadcasts the rows it found, so every rank sees the same data; a
// row holds from its time until the next row's (as -db_switch_schedule's
// entries do), so the conditions at a time are known once a row at or after
// it is in the file.  The run asks for the rows up to the end of its next
// step and waits (sleeping, all ranks) until they are there, the stop file
// appears, or a signal arrives.
#pragma once

#include "base/petsc_compat.hpp"

#include <petscsys.h>

#include <csignal>
#include <limits>
#include <string>
#include <vector>

namespace rcfd {

class FractionSet;
class Pipeline;

class LiveInput {
public:
  /// The conditions rcfd follows, with the column that names each.
  enum Quantity {
    SuperficialVelocity, FeedRate, DischargeRate, GrowthRate, SprayRate, GasTemperature, FeedShare, NumQuantities
  };
  /// Why the input ended.
  enum class End { None, StopFile, Signal };

  LiveInput() = default;
  ~LiveInput(); // the signal handlers it installed are put back
  LiveInput(const LiveInput &) = delete;
  LiveInput &operator=(const LiveInput &) = delete;

  /// Collective.  -live FILE, -live_on_bad_line skip|fail, -live_stop_file,
  /// -live_end, -live_pace, -live_poll.
  PetscErrorCode setFromOptions(MPI_Comm comm);
  bool enabled() const { return !path_.empty(); }
  const std::string &path() const { return path_; }
  /// -live_end [s], or a negative number: none.
  double endTime() const { return end_; }

  /// Collective.  Installs the SIGINT/SIGTERM handlers, waits for the
  /// header and the first row (at time 0), refuses a column rcfd does not
  /// follow (feed shares by the fractions' labels: feed_share_d1.459mm).
  PetscErrorCode start(MPI_Comm comm, const FractionSet &fractions, bool quiet);
  /// Collective.  Reads a whole file of the same format once, neither waiting nor
  /// following it (a forecast's what-if schedule, -forecast_schedule): its sentences name
  /// `option` and the file; a missing file, a malformed line or a file without rows is refused.
  PetscErrorCode readWhole(MPI_Comm comm, const std::string &option, const std::string &file,
                           const FractionSet &fractions);
  /// Whether the file has the column of `q` (FeedShare: all the fractions').
  bool has(Quantity q) const { return q == FeedShare ? !shareColumns_.empty() : column_[q] >= 0; }
  /// The value of q in the row that holds at time t [s] (the last at or before
  /// it, to round-off); NaN without the column.  Feed shares: fraction i.
  double at(Quantity q, double t, int i = 0) const;
  /// The rows read so far: their times and values of q.
  std::size_t numRows() const { return times_.size(); }
  double rowTime(std::size_t k) const { return times_[k]; }
  double rowValue(std::size_t k, Quantity q) const { return rows_[k * width_ + column_[q]]; }
  /// The latest time in the file [s].
  double knownUntil() const { return times_.empty() ? -1.0 : times_.back(); }

  /// Collective.  Returns once the rows cover time `until` [s] (a row at or
  /// after it), or the input ended (*end: the stop file appeared with the
  /// rows short of it, or SIGINT/SIGTERM reached a rank).  `onWait` runs once
  /// before the first sleep (the run flushes its files there).  Between
  /// looks every rank sleeps -live_poll seconds.
  template <typename OnWait> PetscErrorCode waitFor(double until, End *end, OnWait &&onWait) {
    bool waited = false;
    PetscFunctionBeginUser;
    for (;;) {
      PetscCall(exchange(until));
      *end = ended_;
      if (ended_ != End::None || covers(until)) break;
      if (stopSeen_) {
        *end = ended_ = End::StopFile;
        break;
      }
      if (!waited) PetscCall(onWait());
      waited = true;
      sleepSeconds(poll_);
    }
    PetscFunctionReturn(PETSC_SUCCESS);
  }
  /// Whether the rows read so far cover time t (to round-off).
  bool covers(double t) const { return !times_.empty() && t <= times_.back() * (1.0 + 1e-12); }
  /// Collective: whether a signal reached any rank (one reduction).
  PetscErrorCode interrupted(End *end);
  /// -live_pace: sleeps until the wall clock since `pace()` was first called
  /// reaches `simulated` - its simulated time then.
  void pace(double simulated);
  long skippedLines() const { return skipped_; }

private:
  PetscErrorCode exchange(double until);          // rank 0 reads, every rank gets the new rows
  std::string readNew(std::vector<double> *rows); // rank 0: the complete lines appended; an error's sentence
  std::string parseHeader(const std::string &line, const FractionSet &fractions);
  std::string parseRow(const std::string &line, long number, double previous, std::vector<double> *row) const;
  static void sleepSeconds(double seconds);

  MPI_Comm comm_ = MPI_COMM_NULL;
  std::string option_ = "-live"; // names the file in the sentences
  std::string path_, stopFile_;
  bool failOnBadLine_ = true, paced_ = false, quiet_ = false;
  double end_ = -1.0, poll_ = 0.2;
  // The file as read (rank 0): the bytes consumed (complete lines), the line number.
  long long offset_ = 0;
  long lineNumber_ = 0, skipped_ = 0;
  bool headerRead_ = false, whole_ = false; // whole_: the file is complete (a last line without its end counts)
  const FractionSet *fractions_ = nullptr; // the feed shares' labels
  std::string header_;                     // the header line, sent to every rank
  std::vector<std::string> names_;
  // The rows, the same on every rank.
  int width_ = 0;                             // values per row (the time excluded)
  int timeColumn_ = -1;                       // in the file's order
  int column_[NumQuantities] = {-1, -1, -1, -1, -1, -1, -1}; // index in a row's values
  std::vector<int> shareColumns_;             // feed share of each fraction
  std::vector<double> times_, rows_;
  bool stopSeen_ = false;
  End ended_ = End::None;
  double paceWall_ = -1.0, paceSimulated_ = 0.0;
  // The handlers -live replaced, put back by the destructor.
  struct sigaction previousInt_ {}, previousTerm_ {};
  bool handlersInstalled_ = false;
};

/// The granulator's rates in `conditions` at time t [s] onto the operators of `ops` that follow
/// them (growth, feed and its shares, discharge); what it has no column for stays.
void setGranulatorRates(const LiveInput &conditions, double t, const Pipeline &ops);
/// Why a granulator's column of `conditions` has no operator in `ops` to follow it ("the column
/// discharge_rate needs the discharge operator in -pipeline"), or "" when each has one.
std::string granulatorColumnWithoutOperator(const LiveInput &conditions, const Pipeline &ops);

} // namespace rcfd
