// Running processes without a shell (stderr collected), finding a working
// gnuplot on PATH, and running a plot script with it.
#include "gnuplot_process.hpp"

#include <fcntl.h>
#include <sys/stat.h>
#include <sys/types.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cerrno>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <string>
#include <system_error>
#include <utility>
#include <vector>

#include "gnuplot_text.hpp"
#include "lagrangian/errors.hpp"

namespace lagrangian::plots_detail {

namespace {

constexpr const char* kNotFound = "gnuplot not found; install it with: apt-get install gnuplot-nox (plots skipped)";

std::string find_on_path(const std::string& program) {
  const char* path_env = std::getenv("PATH");
  const std::string path = path_env ? path_env : "/usr/local/bin:/usr/bin:/bin";
  std::size_t start = 0;
  while (start <= path.size()) {
    std::size_t end = path.find(':', start);
    if (end == std::string::npos) end = path.size();
    std::string dir = path.substr(start, end - start);
    if (dir.empty()) dir = ".";
    const std::string candidate = dir + "/" + program;
    struct stat st {};
    if (::stat(candidate.c_str(), &st) == 0 && S_ISREG(st.st_mode) && ::access(candidate.c_str(), X_OK) == 0)
      return candidate;
    start = end + 1;
  }
  return {};
}

struct ProcessResult {
  int status = -1;  // exit status, or -1 when it did not exit normally
  std::string err;  // what it wrote on stderr
};

// Runs `exe args...` in directory `cwd` (if not empty) with stdin and stdout
// on /dev/null; collects stderr. No shell is involved, so paths need no quoting.
ProcessResult run_process(const std::string& exe, const std::vector<std::string>& args, const std::string& cwd) {
  std::vector<std::string> argv_store;
  argv_store.push_back(exe);
  argv_store.insert(argv_store.end(), args.begin(), args.end());
  std::vector<char*> argv;
  for (auto& a : argv_store) argv.push_back(a.data());
  argv.push_back(nullptr);

  int fds[2];
  if (::pipe2(fds, O_CLOEXEC) != 0) throw OptionError(std::string("cannot create a pipe: ") + std::strerror(errno));
  const int devnull = ::open("/dev/null", O_RDWR | O_CLOEXEC);
  const pid_t pid = ::fork();
  if (pid < 0) {
    const int e = errno;
    ::close(fds[0]);
    ::close(fds[1]);
    if (devnull >= 0) ::close(devnull);
    throw OptionError("cannot start '" + exe + "': " + std::strerror(e));
  }
  if (pid == 0) {  // child: only async-signal-safe calls
    if (devnull >= 0) {
      ::dup2(devnull, STDIN_FILENO);
      ::dup2(devnull, STDOUT_FILENO);
    }
    ::dup2(fds[1], STDERR_FILENO);
    if (!cwd.empty() && ::chdir(cwd.c_str()) != 0) ::_exit(126);
    ::execv(exe.c_str(), argv.data());
    ::_exit(127);
  }
  ::close(fds[1]);
  if (devnull >= 0) ::close(devnull);
  ProcessResult r;
  char buf[4096];
  while (true) {
    const ssize_t n = ::read(fds[0], buf, sizeof buf);
    if (n > 0) {
      if (r.err.size() < (1u << 20)) r.err.append(buf, static_cast<std::size_t>(n));
    } else if (n == 0 || errno != EINTR) {
      break;
    }
  }
  ::close(fds[0]);
  int wstatus = 0;
  while (::waitpid(pid, &wstatus, 0) < 0 && errno == EINTR) {
  }
  r.status = WIFEXITED(wstatus) ? WEXITSTATUS(wstatus) : -1;
  return r;
}

}  // namespace

void run_script(const std::string& exe, const fs::path& dir, const fs::path& script,
                const std::vector<std::string>& names, bool png, bool svg, PlotResult& result) {
  std::vector<std::string> exts;
  if (png) exts.push_back("png");
  if (svg) exts.push_back("svg");
  std::vector<std::pair<fs::path, fs::path>> outputs;  // partial, final
  for (const std::string& name : names)
    for (const std::string& ext : exts)
      outputs.emplace_back(dir / (name + ".partial." + ext), dir / (name + "." + ext));
  auto remove_outputs = [&] {
    for (const auto& [partial, final_path] : outputs) {
      std::error_code ignore;
      fs::remove(partial, ignore);
      fs::remove(final_path, ignore);
    }
  };
  remove_outputs();  // images of an earlier run would not match this one
  const ProcessResult run = run_process(exe, {"-e", "suffix = '.partial'", script.filename().string()}, dir.string());
  const std::string err = trim(run.err);
  if (run.status != 0) {
    remove_outputs();
    throw OptionError("gnuplot failed on '" + script.string() + "' (exit status " + std::to_string(run.status) +
                      ")" + (err.empty() ? "" : ":\n" + err));
  }
  for (const auto& [partial, final_path] : outputs) {
    std::error_code e1;
    const auto size = fs::file_size(partial, e1);
    if (e1 || size == 0) {
      remove_outputs();
      throw OptionError("gnuplot did not write '" + partial.string() + "' (script '" + script.string() + "')" +
                        (err.empty() ? "" : ":\n" + err));
    }
    fs::rename(partial, final_path, e1);
    if (e1) {
      remove_outputs();
      throw OptionError("cannot rename '" + partial.string() + "' to '" + final_path.string() + "': " + e1.message());
    }
    result.files.push_back(final_path.string());
  }
  result.files.push_back(script.string());
  result.message = "wrote " + std::to_string(outputs.size()) + " plots and the script " +
                   script.filename().string() + " to '" + dir.string() + "'";
  if (!err.empty()) result.message += "; gnuplot said: " + err;
}

std::string working_gnuplot() {
  const std::string exe = find_on_path("gnuplot");
  if (exe.empty()) return {};
  try {
    return run_process(exe, {"--version"}, "").status == 0 ? exe : std::string();
  } catch (const OptionError&) {
    return {};
  }
}

std::string gnuplot_for(bool png, bool svg, PlotResult& result) {
  const std::string exe = working_gnuplot();
  if (exe.empty()) {
    result.message = kNotFound;
    return {};
  }
  result.gnuplot_found = true;
  if (!png && !svg) {
    result.message = "plots skipped: neither png nor svg is enabled";
    return {};
  }
  return exe;
}

}  // namespace lagrangian::plots_detail
