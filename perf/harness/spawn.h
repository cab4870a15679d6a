// Child processes and result files of the perf harness.
//
// Every run executes in a child process: the parent re-executes its own
// binary (/proc/self/exe) with posix_spawn as `superdex_perf run <spec>
// --result-fd 3`, reads the child's single CSV result line from a pipe on fd
// 3, enforces a timeout (SIGKILL to the child's process group), and takes the
// peak RSS from wait4's rusage. No fork without exec: PETSc / MPI do not
// survive a fork, and a crash or hang in one run cannot take the suite down.
#pragma once

#include <cstdio>
#include <string>
#include <vector>

#include "run.h"

namespace superdex::perf {

/// The fd the child writes its result line to.
inline constexpr int kResultFd = 3;

/// Runs `spec` in a child process; the child's stdout and stderr go to
/// `logPath` (removed afterwards when empty). Returns the child's row, with
/// peak_rss_mb from wait4, or a `failed` row (reason `timeout`, `crashed
/// (signal N)`, `exited with status N ...`). `wallSeconds`: spawn to exit.
Row RunInChild(RunSpec const& spec, double timeoutSeconds, std::string const& logPath,
               double& wallSeconds);

/// On SIGINT / SIGTERM, kills the running child's process group before the
/// parent dies (the child has its own group, so the terminal's signal does
/// not reach it).
void InstallInterruptHandler();

// ------------------------------------------------------------- CSV / JSON

/// One CSV line (no newline): cells quoted when they hold a comma, a quote
/// or a newline, quotes doubled.
std::string CsvLine(Row const& row);
/// The CSV header line.
std::string CsvHeader();
/// Parses a line CsvLine wrote; false unless it has exactly kNumColumns cells.
bool ParseCsvLine(std::string const& line, Row& row);
/// One JSON object with the column names as keys (numbers unquoted, empty
/// numeric cells null).
std::string JsonObject(Row const& row);

/// OUT/results.csv (appended and flushed row by row, so that a partial suite
/// leaves a valid file) and OUT/results.json (an array, rewritten after every
/// row and at the end).
class ResultWriter {
 public:
  ResultWriter() = default;
  ResultWriter(ResultWriter const&) = delete;
  ResultWriter& operator=(ResultWriter const&) = delete;
  ~ResultWriter();

  /// Creates DIR (and DIR/ref, DIR/logs) and writes the CSV header.
  bool Open(std::string const& dir, std::string& message);
  bool Append(Row const& row);
  std::vector<Row> const& GetRows() const { return rows_; }

 private:
  bool WriteJson() const;

  std::string dir_;
  std::FILE* csv_ = nullptr;
  std::vector<Row> rows_;
};

}  // namespace superdex::perf
