#pragma once
/// @file Trace records: one JSON object per line, stamped with CLOCK_REALTIME.
///
/// Every process of the testbed can write them (DESIGN.md, "Time, identity, tracing");
/// scripts/ joins them into the latency tables. A record costs well under a microsecond when
/// enabled (formatted into a buffer, written in large blocks) and one branch when disabled.
///
///   {"ts":1732233600123456789,"proc":"its-station","ev":"cam.tx","station":1001,"gdt":4242}

#include <cstdint>
#include <initializer_list>
#include <mutex>
#include <string>
#include <string_view>
#include <variant>

#include <fmt/format.h>

namespace tb::trace {

struct Field {
  using Value = std::variant<std::int64_t, std::uint64_t, double, std::string_view, bool>;
  // Constructors from every integer width keep call sites free of casts.
  Field(std::string_view k, int v) : key(k), value(std::int64_t{v}) {}
  Field(std::string_view k, long v) : key(k), value(std::int64_t{v}) {}
  Field(std::string_view k, long long v) : key(k), value(std::int64_t{v}) {}
  Field(std::string_view k, unsigned v) : key(k), value(std::uint64_t{v}) {}
  Field(std::string_view k, unsigned long v) : key(k), value(std::uint64_t{v}) {}
  Field(std::string_view k, unsigned long long v) : key(k), value(std::uint64_t{v}) {}
  Field(std::string_view k, double v) : key(k), value(v) {}
  Field(std::string_view k, bool v) : key(k), value(v) {}
  Field(std::string_view k, std::string_view v) : key(k), value(v) {}
  Field(std::string_view k, const char* v) : key(k), value(std::string_view{v}) {}

  std::string_view key;  ///< a plain identifier; not escaped
  Value value;
};

/// Writes trace records to a file. Thread-safe. A default-constructed Tracer is disabled.
class Tracer {
 public:
  Tracer() = default;
  /// Opens (appends to) @p path. @throws std::system_error naming the path if it cannot.
  Tracer(const std::string& path, std::string process);
  ~Tracer();
  Tracer(const Tracer&) = delete;
  Tracer& operator=(const Tracer&) = delete;

  bool enabled() const { return fd_ >= 0; }

  /// Records @p event now (CLOCK_REALTIME).
  void record(std::string_view event, std::initializer_list<Field> fields) {
    if (enabled())
      write(now_ns(), event, fields);
  }
  /// Records @p event with a timestamp taken earlier (for example a kernel receive time).
  void record_at(std::int64_t unix_ns, std::string_view event,
                 std::initializer_list<Field> fields) {
    if (enabled())
      write(unix_ns, event, fields);
  }
  /// Writes buffered records to the file.
  void flush();

  static std::int64_t now_ns();

 private:
  void write(std::int64_t ts, std::string_view event, std::initializer_list<Field> fields);
  void flush_locked();

  int fd_ = -1;
  std::string proc_field_;  ///< `,"proc":"<process>","ev":`, escaped once
  std::mutex mutex_;
  fmt::memory_buffer buffer_;
  std::int64_t last_flush_ns_ = 0;
};

/// The process-wide tracer, disabled until configure() is called (programs do so from
/// `--trace FILE` or the TESTBED_TRACE_DIR environment variable).
Tracer& global();
/// Enables the global tracer writing to @p path; an empty path leaves it disabled.
void configure(const std::string& path, const std::string& process);
/// Enables the global tracer at $TESTBED_TRACE_DIR/<process>.jsonl when that variable is set.
/// Returns the path in use, or an empty string.
std::string configure_from_env(const std::string& process);

}  // namespace tb::trace
