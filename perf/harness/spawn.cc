// Child processes and result files of the perf harness (spawn.h).
#include "spawn.h"

#include <fcntl.h>
#include <poll.h>
#include <signal.h>
#include <spawn.h>
#include <sys/resource.h>
#include <sys/stat.h>
#include <sys/syscall.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <chrono>
#include <cmath>
#include <csignal>
#include <cstdlib>
#include <cstring>
#include <filesystem>

extern char** environ;

namespace superdex::perf {
namespace {

using Clock = std::chrono::steady_clock;

/// The child being waited for (0: none), for the interrupt handler.
volatile sig_atomic_t g_child = 0;

void OnInterrupt(int signal) {
  if (g_child > 0) kill(-g_child, SIGKILL);
  std::signal(signal, SIG_DFL);
  raise(signal);
}

/// A pipe whose write end is not fd kResultFd itself (dup2 onto the same fd
/// would leave its close-on-exec flag set); both ends close-on-exec.
bool MakeResultPipe(int fds[2]) {
  if (pipe2(fds, O_CLOEXEC) != 0) return false;
  if (fds[1] == kResultFd) {
    int const moved = fcntl(fds[1], F_DUPFD_CLOEXEC, kResultFd + 1);
    close(fds[1]);
    fds[1] = moved;
  }
  return fds[1] >= 0;
}

/// A `failed` row for a run the child could not report.
Row FailedRow(RunSpec const& spec, std::string const& reason) {
  Row row = RowFromSpec(spec);
  row[kStatus] = "failed";
  row[kReason] = reason;
  return row;
}

/// Spawns `superdex_perf run <spec> --result-fd 3` in its own process group,
/// stdout and stderr to `logPath`, fd 3 to `resultFd`; the pid, or -1.
pid_t Spawn(RunSpec const& spec, int resultFd, std::string const& logPath, std::string& message) {
  std::vector<std::string> args{"superdex_perf", "run"};
  for (std::string& a : SpecToArgs(spec)) args.push_back(std::move(a));
  args.insert(args.end(), {"--result-fd", std::to_string(kResultFd)});
  std::vector<char*> argv;
  for (std::string& a : args) argv.push_back(a.data());
  argv.push_back(nullptr);

  posix_spawn_file_actions_t actions;
  posix_spawnattr_t attributes;
  posix_spawn_file_actions_init(&actions);
  posix_spawn_file_actions_adddup2(&actions, resultFd, kResultFd);
  posix_spawn_file_actions_addopen(&actions, STDOUT_FILENO, logPath.c_str(),
                                   O_WRONLY | O_CREAT | O_TRUNC, 0644);
  posix_spawn_file_actions_adddup2(&actions, STDOUT_FILENO, STDERR_FILENO);
  posix_spawnattr_init(&attributes);
  posix_spawnattr_setflags(&attributes, POSIX_SPAWN_SETPGROUP);
  posix_spawnattr_setpgroup(&attributes, 0);
  pid_t pid = -1;
  int const rc = posix_spawn(&pid, "/proc/self/exe", &actions, &attributes, argv.data(), environ);
  posix_spawn_file_actions_destroy(&actions);
  posix_spawnattr_destroy(&attributes);
  if (rc != 0) {
    message = std::string("posix_spawn failed: ") + std::strerror(rc);
    return -1;
  }
  return pid;
}

/// Reads the child's output and reaps it, killing its process group at the
/// deadline. Waits on a pidfd (the child's exit) and the pipe together; where
/// pidfd_open is missing it polls every 20 ms.
void WaitForChild(pid_t pid, int readFd, Clock::time_point deadline, std::string& output,
                  int& status, rusage& usage, bool& timedOut) {
  int const pidFd = static_cast<int>(syscall(SYS_pidfd_open, pid, 0));
  bool pipeOpen = true;
  timedOut = false;
  while (true) {
    if (wait4(pid, &status, WNOHANG, &usage) == pid) break;
    auto const left =
        std::chrono::duration_cast<std::chrono::milliseconds>(deadline - Clock::now());
    if (left.count() <= 0) {
      kill(-pid, SIGKILL);
      wait4(pid, &status, 0, &usage);
      timedOut = true;
      break;
    }
    pollfd fds[2] = {{pipeOpen ? readFd : -1, POLLIN, 0}, {pidFd, POLLIN, 0}};
    int const timeout = pidFd >= 0 ? static_cast<int>(std::min<long long>(left.count(), 1 << 30))
                                   : static_cast<int>(std::min<long long>(left.count(), 20));
    if (poll(fds, 2, timeout) < 0) {
      if (errno != EINTR) usleep(20000);  // unexpected: fall back to polling wait4
      continue;
    }
    if (fds[0].revents != 0) {
      char buffer[4096];
      ssize_t const n = read(readFd, buffer, sizeof buffer);
      if (n > 0)
        output.append(buffer, static_cast<std::size_t>(n));
      else if (n == 0 || errno != EINTR)
        pipeOpen = false;
    }
  }
  // what the child wrote just before it exited (non-blocking: a helper
  // process that inherited the pipe may keep it open)
  fcntl(readFd, F_SETFL, O_NONBLOCK);
  char buffer[4096];
  for (ssize_t n; pipeOpen && (n = read(readFd, buffer, sizeof buffer)) > 0;)
    output.append(buffer, static_cast<std::size_t>(n));
  if (pidFd >= 0) close(pidFd);
}

/// The row the child's output and exit status give.
Row ChildRow(RunSpec const& spec, std::string const& output, int status, bool timedOut) {
  if (timedOut) return FailedRow(spec, "timeout");
  if (WIFSIGNALED(status))
    return FailedRow(spec, "crashed (signal " + std::to_string(WTERMSIG(status)) + ")");
  // the result is the last complete line
  std::string_view text = output;
  Row row;
  if (text.ends_with('\n')) {
    text.remove_suffix(1);
    std::size_t const newline = text.rfind('\n');
    if (ParseCsvLine(std::string(text.substr(newline == text.npos ? 0 : newline + 1)), row))
      return row;
  }
  return FailedRow(spec, "exited with status " + std::to_string(WEXITSTATUS(status)) +
                             " without a result (see the log)");
}

std::string JsonString(std::string_view text) {
  std::string out = "\"";
  for (char c : text) {
    if (c == '"' || c == '\\') {
      out += '\\';
      out += c;
    } else if (static_cast<unsigned char>(c) < 0x20) {
      char escaped[8];
      std::snprintf(escaped, sizeof escaped, "\\u%04x", c);
      out += escaped;
    } else {
      out += c;
    }
  }
  return out + '"';
}

/// A numeric cell as JSON: the number, or null when empty or not finite.
std::string JsonNumber(std::string const& cell) {
  char* end = nullptr;
  double const value = std::strtod(cell.c_str(), &end);
  return cell.empty() || *end != '\0' || !std::isfinite(value) ? "null" : cell;
}

}  // namespace

Row RunInChild(RunSpec const& spec, double timeoutSeconds, std::string const& logPath,
               double& wallSeconds) {
  auto const start = Clock::now();
  int fds[2];
  std::string message;
  if (!MakeResultPipe(fds)) return FailedRow(spec, std::string("pipe: ") + std::strerror(errno));
  pid_t const pid = Spawn(spec, fds[1], logPath, message);
  close(fds[1]);
  if (pid < 0) {
    close(fds[0]);
    return FailedRow(spec, message);
  }
  g_child = pid;
  std::string output;
  int status = 0;
  rusage usage{};
  bool timedOut = false;
  auto const deadline = start + std::chrono::duration_cast<Clock::duration>(
                                    std::chrono::duration<double>(timeoutSeconds));
  WaitForChild(pid, fds[0], deadline, output, status, usage, timedOut);
  g_child = 0;
  close(fds[0]);
  wallSeconds = std::chrono::duration<double>(Clock::now() - start).count();

  Row row = ChildRow(spec, output, status, timedOut);
  row[kPeakRssMb] = Cell(usage.ru_maxrss / 1024.0, 4);  // KiB → MB
  if (row[kTotalS].empty()) row[kTotalS] = Cell(wallSeconds);
  std::error_code ec;
  if (std::filesystem::file_size(logPath, ec) == 0 && !ec) std::filesystem::remove(logPath, ec);
  return row;
}

void InstallInterruptHandler() {
  std::signal(SIGINT, OnInterrupt);
  std::signal(SIGTERM, OnInterrupt);
}

// ------------------------------------------------------------- CSV / JSON

std::string CsvLine(Row const& row) {
  std::string line;
  for (int c = 0; c < kNumColumns; ++c) {
    if (c > 0) line += ',';
    std::string const& cell = row[c];
    if (cell.find_first_of(",\"\n\r") == std::string::npos) {
      line += cell;
      continue;
    }
    line += '"';
    for (char ch : cell) line += ch == '"' ? std::string("\"\"") : std::string(1, ch);
    line += '"';
  }
  return line;
}

std::string CsvHeader() {
  Row header;
  std::copy(kColumnNames.begin(), kColumnNames.end(), header.begin());
  return CsvLine(header);
}

bool ParseCsvLine(std::string const& line, Row& row) {
  int column = 0;
  std::string cell;
  bool quoted = false;
  for (std::size_t i = 0; i < line.size(); ++i) {
    char const c = line[i];
    if (quoted && c == '"' && i + 1 < line.size() && line[i + 1] == '"') {
      cell += '"';
      ++i;
    } else if (c == '"') {
      quoted = !quoted;
    } else if (c == ',' && !quoted) {
      if (column == kNumColumns - 1) return false;
      row[column++] = std::move(cell);
      cell.clear();
    } else {
      cell += c;
    }
  }
  if (quoted || column != kNumColumns - 1) return false;
  row[column] = std::move(cell);
  return true;
}

std::string JsonObject(Row const& row) {
  std::string json = "{";
  for (int c = 0; c < kNumColumns; ++c) {
    if (c > 0) json += ", ";
    json += JsonString(kColumnNames[c]) + ": ";
    json += IsNumericColumn(c) ? JsonNumber(row[c]) : JsonString(row[c]);
  }
  return json + "}";
}

ResultWriter::~ResultWriter() {
  if (csv_) std::fclose(csv_);
}

bool ResultWriter::Open(std::string const& dir, std::string& message) {
  std::error_code ec;
  for (char const* sub : {"ref", "logs"})
    std::filesystem::create_directories(std::filesystem::path(dir) / sub, ec);
  dir_ = dir;
  std::string const path = dir + "/results.csv";
  csv_ = ec ? nullptr : std::fopen(path.c_str(), "w");
  if (!csv_) {
    message = "cannot create " + path + (ec ? ": " + ec.message() : "");
    return false;
  }
  std::fprintf(csv_, "%s\n", CsvHeader().c_str());
  return std::fflush(csv_) == 0 && WriteJson();
}

bool ResultWriter::Append(Row const& row) {
  rows_.push_back(row);
  std::fprintf(csv_, "%s\n", CsvLine(row).c_str());
  return std::fflush(csv_) == 0 && WriteJson();
}

bool ResultWriter::WriteJson() const {
  // written beside and renamed: a reader never sees a half-written file
  std::string const path = dir_ + "/results.json", temporary = path + ".tmp";
  std::FILE* file = std::fopen(temporary.c_str(), "w");
  if (!file) return false;
  std::fputs("[", file);
  for (std::size_t i = 0; i < rows_.size(); ++i)
    std::fprintf(file, "%s\n  %s", i ? "," : "", JsonObject(rows_[i]).c_str());
  std::fputs("\n]\n", file);
  bool const ok = std::fclose(file) == 0;
  return ok && std::rename(temporary.c_str(), path.c_str()) == 0;
}

}  // namespace superdex::perf
