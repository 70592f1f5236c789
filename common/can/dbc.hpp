#pragma once
/// @file DBC (CAN database) files: parser and signal codec.
///
/// Reads the subset a vehicle database needs: messages (BO_), signals (SG_) in Intel or
/// Motorola byte order, signed or unsigned, with factor, offset, range, unit and receivers,
/// and message cycle times from the "GenMsgCycleTime" attribute (BA_ / BA_DEF_DEF_). Other
/// sections (VERSION, NS_, BS_, BU_, CM_, VAL_, ...) are skipped; multiplexed signals are
/// rejected with an error, since nothing here needs them.

#include <cstdint>
#include <filesystem>
#include <optional>
#include <span>
#include <string>
#include <string_view>
#include <vector>

#include "common/util/expected.hpp"

namespace tb::can {

enum class ByteOrder { kIntel, kMotorola };

struct Signal {
  std::string name;
  unsigned start_bit = 0;  ///< Intel: the LSB's bit; Motorola: the MSB's bit (DBC numbering)
  unsigned length = 1;     ///< bits, 1..64
  ByteOrder byte_order = ByteOrder::kIntel;
  bool is_signed = false;
  double factor = 1.0;
  double offset = 0.0;
  double minimum = 0.0;  ///< physical; minimum == maximum means "no range given"
  double maximum = 0.0;
  std::string unit;
  std::vector<std::string> receivers;

  /// Smallest and largest raw values the signal's bits can hold.
  std::int64_t raw_min() const;
  std::int64_t raw_max() const;
  /// Physical → raw: clamped to [minimum, maximum] (when given), rounded to the nearest step,
  /// then clamped to what the bits can hold. Non-finite values give raw 0.
  std::int64_t to_raw(double physical) const;
  double to_physical(std::int64_t raw) const { return static_cast<double>(raw) * factor + offset; }

  /// Writes @p raw (two's complement for signed signals) into the signal's bits of @p data;
  /// bits beyond the end of @p data are left out (Database::parse checks every signal against
  /// its DLC, so a frame of the DLC's length holds them all).
  void insert_raw(std::int64_t raw, std::span<std::uint8_t> data) const;
  /// Reads the signal's bits, sign-extended for signed signals; bits beyond the end of @p data
  /// (a short frame from the network) read as 0.
  std::int64_t extract_raw(std::span<const std::uint8_t> data) const;

  void encode(double physical, std::span<std::uint8_t> data) const {
    insert_raw(to_raw(physical), data);
  }
  double decode(std::span<const std::uint8_t> data) const { return to_physical(extract_raw(data)); }

  /// Bit positions (byte * 8 + bit, bit 0 = LSB of a byte) of the signal's bits, LSB first.
  std::vector<unsigned> bit_positions() const;
};

struct Message {
  std::uint32_t id = 0;   ///< identifier without flags
  bool extended = false;  ///< 29-bit identifier (DBC marks it with bit 31 of the id)
  std::string name;
  unsigned dlc = 8;
  std::string transmitter;
  std::vector<Signal> signals;
  std::optional<unsigned> cycle_time_ms;  ///< GenMsgCycleTime; empty or 0 = not periodic

  const Signal* find_signal(std::string_view name) const;
};

enum class DbcErrc {
  kCannotOpen,
  kSyntax,
  kBadValue,
  kSignalBeforeMessage,
  kSignalOutsideMessage,
  kSignalOverlap,
  kDuplicateMessage,
  kDuplicateSignal,
  kMultiplexingUnsupported,
  kUnknownMessage,
};
std::string_view to_string(DbcErrc e);

struct DbcError {
  DbcErrc code = DbcErrc::kSyntax;
  std::string file;
  int line = 0;        ///< 1-based; 0 when the whole file is meant
  std::string detail;  ///< what was wrong, with the offending value
  std::string text;    ///< the offending line (trimmed)

  /// "FILE:LINE: <code>: <detail>: `<text>`"
  std::string message() const;
};

struct Database {
  std::vector<Message> messages;

  const Message* find_message(std::uint32_t id, bool extended = false) const;
  const Message* find_message(std::string_view name) const;

  /// Parses DBC text; @p file_name only labels errors.
  static Expected<Database, DbcError> parse(std::string_view text, const std::string& file_name);
  static Expected<Database, DbcError> load(const std::filesystem::path& file);
};

}  // namespace tb::can
