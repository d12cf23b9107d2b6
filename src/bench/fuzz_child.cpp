#include "surgical_sim/bench/fuzz_child.h"

#include <poll.h>
#include <signal.h>
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <cstdio>
#include <exception>
#include <iostream>

namespace surgical_sim::bench {

ChildResult runInChild(const std::function<std::string()>& trial, double timeout_s,
                       rlim_t memory_limit) {
  ChildResult result;
  int fds[2];
  if (pipe(fds) != 0) return result;
  std::fflush(nullptr);
  const auto start = std::chrono::steady_clock::now();
  const pid_t pid = fork();
  if (pid < 0) {
    close(fds[0]);
    close(fds[1]);
    return result;
  }
  if (pid == 0) {
    close(fds[0]);
    const rlimit limit{memory_limit, memory_limit};
    setrlimit(RLIMIT_AS, &limit);
    std::string out;
    try {
      out = trial();
    } catch (const std::exception& e) {
      out = std::string("uncaught exception: ") + e.what();
    } catch (...) {
      out = "uncaught exception of unknown type";
    }
    for (std::size_t sent = 0; sent < out.size();) {
      const ssize_t n = write(fds[1], out.data() + sent, out.size() - sent);
      if (n <= 0) break;
      sent += static_cast<std::size_t>(n);
    }
    _exit(0);
  }
  close(fds[1]);
  const auto elapsed = [&] {
    return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  };
  bool timed_out = false;
  char buffer[4096];
  for (;;) {
    const double left = timeout_s - elapsed();
    if (left <= 0.0) {
      timed_out = true;
      break;
    }
    pollfd p{fds[0], POLLIN, 0};
    const int ready = poll(&p, 1, static_cast<int>(left * 1000.0) + 1);
    if (ready <= 0) continue;  // timeout (checked above) or an interrupted poll
    const ssize_t n = read(fds[0], buffer, sizeof(buffer));
    if (n <= 0) break;
    result.output.append(buffer, static_cast<std::size_t>(n));
  }
  close(fds[0]);
  if (timed_out) kill(pid, SIGKILL);
  int status = 0;
  waitpid(pid, &status, 0);
  result.seconds = elapsed();
  if (timed_out) {
    result.end = ChildResult::End::TimedOut;
  } else if (WIFSIGNALED(status)) {
    result.end = ChildResult::End::Signalled;
    result.signal = WTERMSIG(status);
  } else {
    result.end = ChildResult::End::Finished;
  }
  return result;
}

std::vector<std::string> trialFields(const ChildResult& child, double timeout_s,
                                     std::size_t count) {
  std::vector<std::string> fields(count);
  fields.front() = "crash";
  using End = ChildResult::End;
  if (child.end == End::TimedOut) {
    fields.front() = "hang";
    fields.back() = "no result after " + std::to_string(timeout_s) + " s";
  } else if (child.end == End::Signalled) {
    fields.back() = "killed by signal " + std::to_string(child.signal);
  } else if (child.end == End::ForkFailed) {
    fields.back() = "fork failed";
  } else {
    std::vector<std::size_t> tabs;
    for (std::size_t at = child.output.find('\t');
         at != std::string::npos && tabs.size() + 1 < count; at = child.output.find('\t', at + 1))
      tabs.push_back(at);
    if (tabs.size() + 1 < count) {
      fields.back() = child.output;
    } else {
      std::size_t start = 0;
      for (std::size_t k = 0; k + 1 < count; ++k) {
        fields[k] = child.output.substr(start, tabs[k] - start);
        start = tabs[k] + 1;
      }
      fields.back() = child.output.substr(start);
    }
  }
  return fields;
}

std::string csvField(const std::string& text) {
  std::string out = "\"";
  for (const char c : text) {
    const auto byte = static_cast<unsigned char>(c);
    if (c == '"') {
      out += "\"\"";
    } else if (byte < 0x20 || byte > 0x7e) {
      char hex[5];
      std::snprintf(hex, sizeof(hex), "\\x%02x", byte);
      out += hex;
    } else {
      out += c;
    }
  }
  return out + "\"";
}

std::string parseFuzzArgs(int argc, char** argv, long long min_count,
                          const std::set<std::string>& text_options, const std::string& required,
                          FuzzArgs& out) {
  for (int i = 1; i < argc; ++i) {
    const std::string arg = argv[i];
    if (arg == "--help" || arg == "-h") {
      out.help = true;
      return "";
    }
    if (i + 1 >= argc) return "missing value after " + arg;
    const std::string value = argv[++i];
    if (text_options.count(arg)) {
      out.text[arg] = value;
      continue;
    }
    if (arg != "--seed" && arg != "--count") return "unknown option " + arg;
    try {
      (arg == "--seed" ? out.seed : out.count) = std::stoll(value);
    } catch (const std::exception&) {
      return "bad number '" + value + "' for " + arg;
    }
  }
  if (out.seed < 0 || out.seed > 0xFFFFFFFFLL) return "--seed must be in [0, 2^32)";
  if (out.count < min_count || out.count > 1000000)
    return "--count must be in [" + std::to_string(min_count) + ", 1000000]";
  if (!out.text.count(required)) return required + " is required";
  return "";
}

std::optional<int> fuzzCommandLineExit(const std::string& tool, const std::string& usage, int argc,
                                       char** argv, long long min_count,
                                       const std::set<std::string>& text_options,
                                       const std::string& required, FuzzArgs& out) {
  const std::string problem = parseFuzzArgs(argc, argv, min_count, text_options, required, out);
  if (out.help) {
    std::cout << usage;
    return 0;
  }
  if (problem.empty()) return std::nullopt;
  std::cerr << tool << ": " << problem << "\n" << usage;
  return 2;
}

}  // namespace surgical_sim::bench
