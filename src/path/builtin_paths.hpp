// Constructors of the built-in path kinds, one file each (replay_path.cpp,
// stitching_path.cpp, recorded_path.cpp).  Without arguments a kind waits for
// setFromOptions() and setUp(); with arguments it is ready to step (as made
// by makeFramePath() and makeRecordedPath() in path/frame_path.hpp).
#pragma once

#include "path/frame_path.hpp"

namespace rcfd {

/// -path_start.
std::unique_ptr<FramePath> newReplayPath();
std::unique_ptr<FramePath> newReplayPath(int K, int start);

/// kind: random, markov or quarter.  -path_seed, -path_start,
/// -path_min_length, -path_max_length (random, quarter), -path_band (random,
/// markov), -path_mean_interval (markov), -path_candidates,
/// -path_recurrence_norm (formerly -recurrence_norm).
std::unique_ptr<FramePath> newStitchingPath(const std::string &kind);
/// Throws std::invalid_argument on bad parameters (see makeFramePath()).
std::unique_ptr<FramePath> newStitchingPath(const std::string &kind, int K,
                                            const std::vector<double> &recurrence,
                                            const PathParams &params);

/// -path_file.
std::unique_ptr<FramePath> newRecordedPath();

/// Throws std::invalid_argument unless K >= 2 and the start frame is one of them.
void checkPathStart(const std::string &kind, int K, const PathParams &params);

/// "<kind> path: <what>", the start of every parameter error.
std::string pathParameterError(const std::string &kind, const std::string &what);

} // namespace rcfd
