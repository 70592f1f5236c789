#include "common/trace/tracer.hpp"

#include <fcntl.h>
#include <unistd.h>

#include <cerrno>
#include <cstdlib>
#include <ctime>
#include <memory>
#include <system_error>

#include <fmt/compile.h>

namespace tb::trace {
namespace {

constexpr std::size_t kFlushThreshold = 64 * 1024;
constexpr std::int64_t kFlushEveryNs = 1'000'000'000;

void append_escaped(fmt::memory_buffer& out, std::string_view s) {
  out.push_back('"');
  for (const char c : s) {
    switch (c) {
      case '"':
        out.append(std::string_view{"\\\""});
        break;
      case '\\':
        out.append(std::string_view{"\\\\"});
        break;
      case '\n':
        out.append(std::string_view{"\\n"});
        break;
      case '\t':
        out.append(std::string_view{"\\t"});
        break;
      default:
        if (static_cast<unsigned char>(c) < 0x20) {
          fmt::format_to(std::back_inserter(out), "\\u{:04x}", static_cast<unsigned>(c));
        } else {
          out.push_back(c);
        }
    }
  }
  out.push_back('"');
}

// Integers through format_int and doubles through a compiled format: no format string is parsed
// per record (a full station writes ~2,000 records a second at 49 neighbours).
void append_integer(fmt::memory_buffer& out, auto v) {
  const fmt::format_int text(v);
  out.append(text.data(), text.data() + text.size());
}

struct ValueWriter {
  fmt::memory_buffer& out;
  void operator()(std::int64_t v) const { append_integer(out, v); }
  void operator()(std::uint64_t v) const { append_integer(out, v); }
  void operator()(double v) const {
    // JSON has no NaN or infinity; null keeps the line parseable.
    if (v != v || v - v != 0.0) {
      out.append(std::string_view{"null"});
    } else {
      fmt::format_to(std::back_inserter(out), FMT_COMPILE("{}"), v);
    }
  }
  void operator()(std::string_view v) const { append_escaped(out, v); }
  void operator()(bool v) const { out.append(v ? std::string_view{"true"} : "false"); }
};

}  // namespace

Tracer::Tracer(const std::string& path, std::string process) {
  fmt::memory_buffer escaped;
  escaped.append(std::string_view{",\"proc\":"});
  append_escaped(escaped, process);
  escaped.append(std::string_view{",\"ev\":"});
  proc_field_ = fmt::to_string(escaped);
  fd_ = ::open(path.c_str(), O_WRONLY | O_CREAT | O_APPEND | O_CLOEXEC, 0644);
  if (fd_ < 0)
    throw std::system_error(errno, std::generic_category(), "trace file " + path);
}

Tracer::~Tracer() {
  if (fd_ >= 0) {
    flush();
    ::close(fd_);
  }
}

std::int64_t Tracer::now_ns() {
  timespec ts{};
  ::clock_gettime(CLOCK_REALTIME, &ts);
  return std::int64_t{ts.tv_sec} * 1'000'000'000 + ts.tv_nsec;
}

void Tracer::write(std::int64_t ts, std::string_view event, std::initializer_list<Field> fields) {
  std::lock_guard lock(mutex_);
  buffer_.append(std::string_view{"{\"ts\":"});
  append_integer(buffer_, ts);
  buffer_.append(std::string_view{proc_field_});
  append_escaped(buffer_, event);
  for (const Field& f : fields) {
    buffer_.push_back(',');
    buffer_.push_back('"');
    buffer_.append(f.key);
    buffer_.append(std::string_view{"\":"});
    std::visit(ValueWriter{buffer_}, f.value);
  }
  buffer_.append(std::string_view{"}\n"});
  // Large blocks keep records cheap; the age bound keeps what a killed process loses small.
  if (buffer_.size() >= kFlushThreshold || ts - last_flush_ns_ >= kFlushEveryNs) {
    flush_locked();
    last_flush_ns_ = ts;
  }
}

void Tracer::flush() {
  std::lock_guard lock(mutex_);
  flush_locked();
}

void Tracer::flush_locked() {
  const char* p = buffer_.data();
  std::size_t left = buffer_.size();
  while (left > 0) {
    const ssize_t n = ::write(fd_, p, left);
    if (n < 0) {
      if (errno == EINTR)
        continue;
      break;  // a full disk must not stop the testbed; the records are lost, the run goes on
    }
    p += n;
    left -= static_cast<std::size_t>(n);
  }
  buffer_.clear();
}

namespace {
std::unique_ptr<Tracer>& global_slot() {
  static std::unique_ptr<Tracer> tracer = std::make_unique<Tracer>();
  return tracer;
}
}  // namespace

Tracer& global() {
  return *global_slot();
}

void configure(const std::string& path, const std::string& process) {
  if (path.empty())
    return;
  global_slot() = std::make_unique<Tracer>(path, process);
}

std::string configure_from_env(const std::string& process) {
  const char* dir = std::getenv("TESTBED_TRACE_DIR");
  if (dir == nullptr || *dir == '\0')
    return {};
  std::string path = std::string(dir) + "/" + process + ".jsonl";
  configure(path, process);
  return path;
}

}  // namespace tb::trace
