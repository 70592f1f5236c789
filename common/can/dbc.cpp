#include "common/can/dbc.hpp"

#include <algorithm>
#include <charconv>
#include <cmath>
#include <fstream>
#include <sstream>
#include <unordered_set>

#include <fmt/format.h>

namespace tb::can {

// ---- Signal codec ------------------------------------------------------------------------------

std::int64_t Signal::raw_min() const {
  if (!is_signed)
    return 0;
  return length >= 64 ? INT64_MIN : -(std::int64_t{1} << (length - 1));
}

std::int64_t Signal::raw_max() const {
  if (is_signed)
    return length >= 64 ? INT64_MAX : (std::int64_t{1} << (length - 1)) - 1;
  // Unsigned 64-bit signals are limited to what an int64 holds; nothing here needs more.
  return length >= 63 ? INT64_MAX : (std::int64_t{1} << length) - 1;
}

std::int64_t Signal::to_raw(double physical) const {
  if (!std::isfinite(physical))
    return 0;
  if (minimum < maximum)
    physical = std::clamp(physical, minimum, maximum);
  const double raw = std::round((physical - offset) / factor);
  const auto lo = static_cast<double>(raw_min());
  const auto hi = static_cast<double>(raw_max());
  if (raw <= lo)
    return raw_min();
  if (raw >= hi)
    return raw_max();
  return static_cast<std::int64_t>(raw);
}

namespace {

/// Calls f(position, bit_index) for every bit, bit_index 0 = the raw value's LSB.
template <typename F>
void for_each_bit(const Signal& s, F&& f) {
  if (s.byte_order == ByteOrder::kIntel) {
    for (unsigned i = 0; i < s.length; ++i)
      f(s.start_bit + i, i);
    return;
  }
  // Motorola (big-endian): the start bit is the MSB; within a byte bits run from 7 down to 0,
  // then continue at bit 7 of the next byte ("sawtooth" numbering of DBC files).
  unsigned pos = s.start_bit;
  for (unsigned n = 0; n < s.length; ++n) {
    f(pos, s.length - 1 - n);
    pos = (pos % 8 == 0) ? pos + 15 : pos - 1;
  }
}

}  // namespace

std::vector<unsigned> Signal::bit_positions() const {
  std::vector<unsigned> out(length);
  for_each_bit(*this, [&](unsigned pos, unsigned bit) { out[bit] = pos; });
  return out;
}

void Signal::insert_raw(std::int64_t raw, std::span<std::uint8_t> data) const {
  const auto u = static_cast<std::uint64_t>(raw);
  if (byte_order == ByteOrder::kIntel && start_bit % 8 == 0 && length % 8 == 0 &&
      start_bit / 8 + length / 8 <= data.size()) {
    // Whole little-endian bytes: the common case, done without the bit loop.
    for (unsigned b = 0; b < length / 8; ++b)
      data[start_bit / 8 + b] = static_cast<std::uint8_t>(u >> (8 * b));
    return;
  }
  for_each_bit(*this, [&](unsigned pos, unsigned bit) {
    if (pos / 8 >= data.size())
      return;  // a frame shorter than the DBC says: write what fits, never past the end
    const auto mask = static_cast<std::uint8_t>(1u << (pos % 8));
    if ((u >> bit) & 1u)
      data[pos / 8] |= mask;
    else
      data[pos / 8] &= static_cast<std::uint8_t>(~mask);
  });
}

std::int64_t Signal::extract_raw(std::span<const std::uint8_t> data) const {
  std::uint64_t u = 0;
  if (byte_order == ByteOrder::kIntel && start_bit % 8 == 0 && length % 8 == 0 &&
      start_bit / 8 + length / 8 <= data.size()) {
    // Whole little-endian bytes, as insert_raw: a station decodes every vehicle frame's signals.
    for (unsigned b = 0; b < length / 8; ++b)
      u |= std::uint64_t{data[start_bit / 8 + b]} << (8 * b);
  } else {
    for_each_bit(*this, [&](unsigned pos, unsigned bit) {
      if (pos / 8 < data.size() && ((data[pos / 8] >> (pos % 8)) & 1u))
        u |= std::uint64_t{1} << bit;
    });
  }
  if (is_signed && length < 64 && ((u >> (length - 1)) & 1u))
    u |= ~std::uint64_t{0} << length;
  return static_cast<std::int64_t>(u);
}

const Signal* Message::find_signal(std::string_view n) const {
  for (const Signal& s : signals)
    if (s.name == n)
      return &s;
  return nullptr;
}

const Message* Database::find_message(std::uint32_t id, bool extended) const {
  for (const Message& m : messages)
    if (m.id == id && m.extended == extended)
      return &m;
  return nullptr;
}

const Message* Database::find_message(std::string_view n) const {
  for (const Message& m : messages)
    if (m.name == n)
      return &m;
  return nullptr;
}

// ---- Errors ------------------------------------------------------------------------------------

std::string_view to_string(DbcErrc e) {
  switch (e) {
    case DbcErrc::kCannotOpen:
      return "cannot open file";
    case DbcErrc::kSyntax:
      return "syntax error";
    case DbcErrc::kBadValue:
      return "bad value";
    case DbcErrc::kSignalBeforeMessage:
      return "signal outside a message";
    case DbcErrc::kSignalOutsideMessage:
      return "signal does not fit its message";
    case DbcErrc::kSignalOverlap:
      return "signals overlap";
    case DbcErrc::kDuplicateMessage:
      return "duplicate message";
    case DbcErrc::kDuplicateSignal:
      return "duplicate signal";
    case DbcErrc::kMultiplexingUnsupported:
      return "multiplexed signals are not supported";
    case DbcErrc::kUnknownMessage:
      return "unknown message";
  }
  return "unknown DBC error";
}

std::string DbcError::message() const {
  std::string out = line > 0 ? fmt::format("{}:{}: {}", file, line, to_string(code))
                             : fmt::format("{}: {}", file, to_string(code));
  if (!detail.empty())
    out += ": " + detail;
  if (!text.empty())
    out += fmt::format(": `{}`", text);
  return out;
}

// ---- Parser ------------------------------------------------------------------------------------

namespace {

constexpr std::string_view kCycleTimeAttribute = "GenMsgCycleTime";
/// Vector tools keep signals that belong to no message in this pseudo-message.
constexpr std::string_view kIndependentSignals = "VECTOR__INDEPENDENT_SIG_MSG";

std::string_view trim(std::string_view s) {
  const auto b = s.find_first_not_of(" \t\r\n");
  if (b == std::string_view::npos)
    return {};
  const auto e = s.find_last_not_of(" \t\r\n");
  return s.substr(b, e - b + 1);
}

bool is_ident_char(char c) {
  return (c >= 'A' && c <= 'Z') || (c >= 'a' && c <= 'z') || (c >= '0' && c <= '9') || c == '_';
}

/// A character cursor over one statement.
class Cursor {
 public:
  explicit Cursor(std::string_view s) : s_(s) {}
  void ws() {
    while (i_ < s_.size() && (s_[i_] == ' ' || s_[i_] == '\t' || s_[i_] == '\r' || s_[i_] == '\n'))
      ++i_;
  }
  bool at_end() {
    ws();
    return i_ >= s_.size();
  }
  char peek() {
    ws();
    return i_ < s_.size() ? s_[i_] : '\0';
  }
  bool eat(char c) {
    ws();
    if (i_ < s_.size() && s_[i_] == c) {
      ++i_;
      return true;
    }
    return false;
  }
  /// One character without skipping blanks first (inside "0|16@1+").
  bool eat_now(char c) {
    if (i_ < s_.size() && s_[i_] == c) {
      ++i_;
      return true;
    }
    return false;
  }
  std::optional<std::string_view> ident() {
    ws();
    const std::size_t b = i_;
    while (i_ < s_.size() && is_ident_char(s_[i_]))
      ++i_;
    if (i_ == b)
      return std::nullopt;
    return s_.substr(b, i_ - b);
  }
  std::optional<std::uint64_t> uinteger() {
    ws();
    std::uint64_t v = 0;
    const auto [p, ec] = std::from_chars(s_.data() + i_, s_.data() + s_.size(), v);
    if (ec != std::errc{})
      return std::nullopt;
    i_ = static_cast<std::size_t>(p - s_.data());
    return v;
  }
  std::optional<double> number() {
    ws();
    if (i_ < s_.size() && s_[i_] == '+')
      ++i_;
    double v = 0;
    const auto [p, ec] = std::from_chars(s_.data() + i_, s_.data() + s_.size(), v);
    if (ec != std::errc{} || !std::isfinite(v))
      return std::nullopt;
    i_ = static_cast<std::size_t>(p - s_.data());
    return v;
  }
  std::optional<std::string> quoted() {
    ws();
    if (i_ >= s_.size() || s_[i_] != '"')
      return std::nullopt;
    ++i_;
    std::string out;
    while (i_ < s_.size() && s_[i_] != '"') {
      if (s_[i_] == '\\' && i_ + 1 < s_.size())
        ++i_;
      out += s_[i_++];
    }
    if (i_ >= s_.size())
      return std::nullopt;
    ++i_;
    return out;
  }
  std::string_view rest() {
    ws();
    return s_.substr(i_);
  }

 private:
  std::string_view s_;
  std::size_t i_ = 0;
};

struct CycleTimeAssignment {
  int line;
  std::string text;
  std::uint32_t raw_id;
  double value;
};

class Parser {
 public:
  Parser(std::string_view text, const std::string& file) : text_(text), file_(file) {}

  Expected<Database, DbcError> run() {
    std::vector<std::string_view> lines;
    for (std::size_t b = 0; b <= text_.size();) {
      const auto e = text_.find('\n', b);
      const auto end = e == std::string_view::npos ? text_.size() : e;
      lines.push_back(text_.substr(b, end - b));
      if (e == std::string_view::npos)
        break;
      b = e + 1;
    }

    bool in_ns = false;
    for (std::size_t n = 0; n < lines.size(); ++n) {
      const std::string_view raw = lines[n];
      const std::string_view line = trim(raw);
      line_ = static_cast<int>(n + 1);
      text_line_ = line;
      if (line.empty() || line.starts_with("//"))
        continue;
      const bool indented = raw.front() == ' ' || raw.front() == '\t';
      if (in_ns && indented)
        continue;  // the keyword list of NS_
      in_ns = false;

      Cursor c(line);
      const auto keyword = c.ident();
      if (!keyword)
        return fail(DbcErrc::kSyntax, "expected a keyword");
      if (*keyword == "NS_") {
        in_ns = true;
      } else if (*keyword == "BO_") {
        if (auto r = parse_message(c); !r)
          return Unexpected{*r.error};
      } else if (*keyword == "SG_") {
        if (auto r = parse_signal(c); !r)
          return Unexpected{*r.error};
      } else if (*keyword == "VERSION" || *keyword == "BS_" || *keyword == "BU_") {
        // Single-line sections that say nothing about frame layout.
      } else if (is_statement_keyword(*keyword)) {
        // Ends with ';' outside quotes, possibly lines later (comments hold newlines).
        const int first_line = line_;
        std::string statement(raw);
        std::size_t last = n;
        while (!has_terminator(statement)) {
          if (++last >= lines.size()) {
            line_ = first_line;
            return fail(DbcErrc::kSyntax, "statement does not end with ';'");
          }
          statement += '\n';
          statement += lines[last];
        }
        n = last;
        line_ = first_line;
        if (*keyword == "BA_" || *keyword == "BA_DEF_DEF_") {
          if (auto r = parse_attribute(*keyword, statement); !r)
            return Unexpected{*r.error};
        }
      } else {
        return fail(DbcErrc::kSyntax, fmt::format("unknown keyword '{}'", *keyword));
      }
    }
    return finish();
  }

 private:
  // A tiny stand-in for Expected<void, DbcError>.
  struct Status {
    std::optional<DbcError> error;
    explicit operator bool() const { return !error; }
  };
  static Status ok() { return {}; }
  Status fail_status(DbcErrc code, std::string detail) {
    return Status{make_error(code, std::move(detail))};
  }
  DbcError make_error(DbcErrc code, std::string detail) const {
    return DbcError{code, file_, line_, std::move(detail), std::string(text_line_)};
  }
  Unexpected<DbcError> fail(DbcErrc code, std::string detail) const {
    return Unexpected{make_error(code, std::move(detail))};
  }

  static bool is_statement_keyword(std::string_view k) {
    static const std::unordered_set<std::string_view> kStatements{
        "CM_",           "BA_DEF_",         "BA_DEF_DEF_", "BA_",          "BA_DEF_REL_",
        "BA_REL_",       "BA_DEF_DEF_REL_", "VAL_",        "VAL_TABLE_",   "SIG_GROUP_",
        "SIG_VALTYPE_",  "BO_TX_BU_",       "EV_",         "ENVVAR_DATA_", "SGTYPE_",
        "SIG_TYPE_REF_", "SGTYPE_VAL_",     "CAT_DEF_",    "CAT_",         "FILTER",
        "SIG_MUL_VAL_"};
    return kStatements.contains(k);
  }

  static bool has_terminator(std::string_view s) {
    bool in_quotes = false;
    for (std::size_t i = 0; i < s.size(); ++i) {
      if (s[i] == '\\' && in_quotes) {
        ++i;
      } else if (s[i] == '"') {
        in_quotes = !in_quotes;
      } else if (s[i] == ';' && !in_quotes) {
        return true;
      }
    }
    return false;
  }

  // BO_ <id> <name>: <dlc> <transmitter>
  Status parse_message(Cursor& c) {
    const auto raw_id = c.uinteger();
    if (!raw_id || *raw_id > 0xFFFFFFFFull)
      return fail_status(DbcErrc::kSyntax, "expected a message identifier after BO_");
    const auto name = c.ident();
    if (!name)
      return fail_status(DbcErrc::kSyntax, "expected a message name");
    if (!c.eat(':'))
      return fail_status(DbcErrc::kSyntax,
                         fmt::format("expected ':' after message name '{}'", *name));
    const auto dlc = c.uinteger();
    if (!dlc)
      return fail_status(DbcErrc::kSyntax, "expected the message length (DLC)");
    const auto tx = c.ident();
    if (!tx || !c.at_end())
      return fail_status(DbcErrc::kSyntax, "expected one transmitter node after the length");

    current_ = nullptr;
    if (*name == kIndependentSignals) {
      skipping_ = true;
      return ok();
    }
    skipping_ = false;
    Message m;
    m.extended = (*raw_id & 0x80000000ull) != 0;
    m.id = static_cast<std::uint32_t>(*raw_id & 0x1FFFFFFFull);
    if (!m.extended && m.id > 0x7FF)
      return fail_status(DbcErrc::kBadValue,
                         fmt::format("standard identifier {} exceeds 0x7FF (set bit 31 for an "
                                     "extended identifier)",
                                     *raw_id));
    if (*dlc > 64)
      return fail_status(DbcErrc::kBadValue,
                         fmt::format("message length {} exceeds 64 bytes", *dlc));
    m.name = std::string(*name);
    m.dlc = static_cast<unsigned>(*dlc);
    m.transmitter = std::string(*tx);
    for (const Message& other : db_.messages) {
      if (other.name == m.name)
        return fail_status(DbcErrc::kDuplicateMessage, fmt::format("name '{}' used twice", m.name));
      if (other.id == m.id && other.extended == m.extended)
        return fail_status(
            DbcErrc::kDuplicateMessage,
            fmt::format("identifier {} used by '{}' and '{}'", m.id, other.name, m.name));
    }
    db_.messages.push_back(std::move(m));
    current_ = &db_.messages.back();
    return ok();
  }

  // SG_ <name> : <start>|<len>@<order><sign> (<factor>,<offset>) [<min>|<max>] "<unit>" <rx>
  Status parse_signal(Cursor& c) {
    if (skipping_)
      return ok();
    if (!current_)
      return fail_status(DbcErrc::kSignalBeforeMessage, "SG_ must follow a BO_ line");
    Signal s;
    const auto name = c.ident();
    if (!name)
      return fail_status(DbcErrc::kSyntax, "expected a signal name");
    s.name = std::string(*name);
    if (c.peek() != ':') {
      const auto mux = c.ident();
      if (mux && (*mux == "M" || (mux->front() == 'm')))
        return fail_status(DbcErrc::kMultiplexingUnsupported,
                           fmt::format("signal '{}' has multiplex indicator '{}'", s.name, *mux));
      return fail_status(DbcErrc::kSyntax,
                         fmt::format("expected ':' after signal name '{}'", s.name));
    }
    c.eat(':');
    const auto start = c.uinteger();
    if (!start || !c.eat_now('|'))
      return fail_status(DbcErrc::kSyntax,
                         fmt::format("signal '{}': expected <start>|<length>", s.name));
    const auto length = c.uinteger();
    if (!length || !c.eat_now('@'))
      return fail_status(DbcErrc::kSyntax,
                         fmt::format("signal '{}': expected <length>@<order>", s.name));
    if (c.eat_now('0'))
      s.byte_order = ByteOrder::kMotorola;
    else if (c.eat_now('1'))
      s.byte_order = ByteOrder::kIntel;
    else
      return fail_status(
          DbcErrc::kSyntax,
          fmt::format("signal '{}': byte order must be 0 (Motorola) or 1 (Intel)", s.name));
    if (c.eat_now('-'))
      s.is_signed = true;
    else if (!c.eat_now('+'))
      return fail_status(
          DbcErrc::kSyntax,
          fmt::format("signal '{}': expected '+' or '-' after the byte order", s.name));
    if (*length < 1 || *length > 64)
      return fail_status(DbcErrc::kBadValue,
                         fmt::format("signal '{}': length {} not in 1..64", s.name, *length));
    if (*start > 511)
      return fail_status(DbcErrc::kBadValue,
                         fmt::format("signal '{}': start bit {} beyond 64 bytes", s.name, *start));
    s.start_bit = static_cast<unsigned>(*start);
    s.length = static_cast<unsigned>(*length);

    std::optional<double> factor, offset, minimum, maximum;
    if (!c.eat('(') || !(factor = c.number()) || !c.eat(',') || !(offset = c.number()) ||
        !c.eat(')'))
      return fail_status(DbcErrc::kSyntax,
                         fmt::format("signal '{}': expected (<factor>,<offset>)", s.name));
    if (!c.eat('[') || !(minimum = c.number()) || !c.eat('|') || !(maximum = c.number()) ||
        !c.eat(']'))
      return fail_status(DbcErrc::kSyntax,
                         fmt::format("signal '{}': expected [<min>|<max>]", s.name));
    if (*factor == 0.0)
      return fail_status(DbcErrc::kBadValue, fmt::format("signal '{}': factor 0", s.name));
    if (*minimum > *maximum)
      return fail_status(DbcErrc::kBadValue, fmt::format("signal '{}': minimum {} above maximum {}",
                                                         s.name, *minimum, *maximum));
    s.factor = *factor;
    s.offset = *offset;
    s.minimum = *minimum;
    s.maximum = *maximum;
    const auto unit = c.quoted();
    if (!unit)
      return fail_status(DbcErrc::kSyntax,
                         fmt::format("signal '{}': expected a quoted unit", s.name));
    s.unit = *unit;
    while (!c.at_end()) {
      const auto rx = c.ident();
      if (!rx)
        return fail_status(DbcErrc::kSyntax, fmt::format("signal '{}': bad receiver list", s.name));
      s.receivers.emplace_back(*rx);
      c.eat(',');
    }

    if (current_->find_signal(s.name))
      return fail_status(DbcErrc::kDuplicateSignal,
                         fmt::format("'{}' appears twice in message '{}'", s.name, current_->name));
    std::vector<bool> used(current_->dlc * 8, false);
    for (const Signal& other : current_->signals)
      for (unsigned p : other.bit_positions())
        used[p] = true;
    for (unsigned p : s.bit_positions()) {
      if (p >= current_->dlc * 8)
        return fail_status(DbcErrc::kSignalOutsideMessage,
                           fmt::format("signal '{}' reaches bit {} of a {}-byte message '{}'",
                                       s.name, p, current_->dlc, current_->name));
      if (used[p])
        return fail_status(
            DbcErrc::kSignalOverlap,
            fmt::format("signal '{}' uses bit {} of message '{}' that another signal uses", s.name,
                        p, current_->name));
    }
    current_->signals.push_back(std::move(s));
    return ok();
  }

  // BA_DEF_DEF_ "GenMsgCycleTime" <value>;   BA_ "GenMsgCycleTime" BO_ <id> <value>;
  Status parse_attribute(std::string_view keyword, const std::string& statement) {
    Cursor c(statement);
    c.ident();
    const auto name = c.quoted();
    if (!name)
      return fail_status(DbcErrc::kSyntax, "expected a quoted attribute name");
    if (*name != kCycleTimeAttribute)
      return ok();
    if (keyword == "BA_DEF_DEF_") {
      const auto v = c.number();
      if (!v || !c.eat(';'))
        return fail_status(DbcErrc::kSyntax, "expected BA_DEF_DEF_ \"GenMsgCycleTime\" <ms>;");
      if (*v < 0 || *v != std::floor(*v))
        return fail_status(DbcErrc::kBadValue,
                           fmt::format("cycle time {} is not a whole number of ms", *v));
      default_cycle_ms_ = static_cast<unsigned>(*v);
      return ok();
    }
    const auto object = c.ident();
    if (!object || *object != "BO_")
      return fail_status(DbcErrc::kSyntax,
                         "GenMsgCycleTime applies to messages: expected BO_ <id>");
    const auto id = c.uinteger();
    const auto v = c.number();
    if (!id || !v || !c.eat(';'))
      return fail_status(DbcErrc::kSyntax, "expected BA_ \"GenMsgCycleTime\" BO_ <id> <ms>;");
    if (*v < 0 || *v != std::floor(*v) || *v > 3'600'000)
      return fail_status(DbcErrc::kBadValue,
                         fmt::format("cycle time {} is not a whole number of ms", *v));
    cycle_times_.push_back(
        {line_, std::string(trim(statement)), static_cast<std::uint32_t>(*id), *v});
    return ok();
  }

  Expected<Database, DbcError> finish() {
    for (Message& m : db_.messages)
      if (default_cycle_ms_ > 0)
        m.cycle_time_ms = default_cycle_ms_;
    for (const auto& a : cycle_times_) {
      const bool extended = (a.raw_id & 0x80000000u) != 0;
      Message* target = nullptr;
      for (Message& m : db_.messages)
        if (m.id == (a.raw_id & 0x1FFFFFFFu) && m.extended == extended)
          target = &m;
      if (!target)
        return Unexpected{DbcError{
            DbcErrc::kUnknownMessage, file_, a.line,
            fmt::format("GenMsgCycleTime for message {} which has no BO_", a.raw_id), a.text}};
      if (a.value > 0)
        target->cycle_time_ms = static_cast<unsigned>(a.value);
      else
        target->cycle_time_ms.reset();
    }
    return std::move(db_);
  }

  std::string_view text_;
  std::string file_;
  int line_ = 0;
  std::string_view text_line_;
  Database db_;
  Message* current_ = nullptr;
  bool skipping_ = false;
  unsigned default_cycle_ms_ = 0;
  std::vector<CycleTimeAssignment> cycle_times_;
};

}  // namespace

Expected<Database, DbcError> Database::parse(std::string_view text, const std::string& file_name) {
  return Parser(text, file_name).run();
}

Expected<Database, DbcError> Database::load(const std::filesystem::path& file) {
  std::ifstream in(file, std::ios::binary);
  if (!in)
    return Unexpected{
        DbcError{DbcErrc::kCannotOpen, file.string(), 0, "no such readable file", ""}};
  std::ostringstream ss;
  ss << in.rdbuf();
  return parse(ss.str(), file.string());
}

}  // namespace tb::can
