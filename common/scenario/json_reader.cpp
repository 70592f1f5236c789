#include "common/scenario/json_reader.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

#include <fmt/format.h>

namespace tb::scenario::detail {
namespace {

std::string type_name(const nlohmann::json& j) {
  if (j.is_number_integer() || j.is_number_unsigned())
    return "an integer";
  if (j.is_number_float())
    return "a number";
  if (j.is_string())
    return "a string";
  if (j.is_boolean())
    return "a boolean";
  if (j.is_null())
    return "null";
  if (j.is_array())
    return "an array";
  if (j.is_object())
    return "an object";
  return j.type_name();
}

std::string escape_pointer_token(std::string_view key) {
  std::string out;
  for (char c : key) {
    if (c == '~') {
      out += "~0";
    } else if (c == '/') {
      out += "~1";
    } else {
      out += c;
    }
  }
  return out;
}

std::size_t edit_distance(std::string_view a, std::string_view b) {
  std::vector<std::size_t> prev(b.size() + 1), cur(b.size() + 1);
  for (std::size_t j = 0; j <= b.size(); ++j)
    prev[j] = j;
  for (std::size_t i = 1; i <= a.size(); ++i) {
    cur[0] = i;
    for (std::size_t j = 1; j <= b.size(); ++j) {
      cur[j] = std::min({prev[j] + 1, cur[j - 1] + 1, prev[j - 1] + (a[i - 1] != b[j - 1])});
    }
    std::swap(prev, cur);
  }
  return prev[b.size()];
}

std::string format_number(double v) {
  return fmt::format("{}", v);
}

}  // namespace

std::string suggestion(std::string_view unknown, const std::vector<std::string>& known) {
  std::string best;
  std::size_t best_d = std::numeric_limits<std::size_t>::max();
  for (const auto& k : known) {
    const std::size_t d = edit_distance(unknown, k);
    if (d < best_d) {
      best_d = d;
      best = k;
    }
  }
  if (best.empty() || best_d > std::max<std::size_t>(2, unknown.size() / 3))
    return {};
  return best;
}

void Node::fail(const std::string& reason) const {
  throw ScenarioError(*file_, path_, reason);
}

double Node::number(double min, double max) const {
  if (!value_->is_number())
    fail("expected a number, found " + type_name(*value_));
  const double v = value_->get<double>();
  if (!std::isfinite(v) || v < min || v > max) {
    fail(fmt::format("value {} is out of range [{}, {}]", format_number(v), format_number(min),
                     format_number(max)));
  }
  return v;
}

long long Node::integer(long long min, long long max) const {
  if (value_->is_number_float()) {
    const double d = value_->get<double>();
    if (d != std::floor(d))
      fail("expected an integer, found " + format_number(d));
  } else if (!value_->is_number()) {
    fail("expected an integer, found " + type_name(*value_));
  }
  // Unsigned values above INT64_MAX and floats beyond the range are out of range, not wrapped.
  if (value_->is_number_unsigned() &&
      value_->get<unsigned long long>() > static_cast<unsigned long long>(max)) {
    fail(fmt::format("value {} is out of range [{}, {}]", value_->get<unsigned long long>(), min,
                     max));
  }
  const double as_double = value_->get<double>();
  if (as_double < static_cast<double>(min) - 0.5 || as_double > static_cast<double>(max) + 0.5) {
    fail(fmt::format("value {} is out of range [{}, {}]", value_->dump(), min, max));
  }
  const long long v = value_->get<long long>();
  if (v < min || v > max)
    fail(fmt::format("value {} is out of range [{}, {}]", v, min, max));
  return v;
}

std::string Node::string() const {
  if (!value_->is_string())
    fail("expected a string, found " + type_name(*value_));
  return value_->get<std::string>();
}

bool Node::boolean() const {
  if (!value_->is_boolean())
    fail("expected true or false, found " + type_name(*value_));
  return value_->get<bool>();
}

std::string Node::choice(std::initializer_list<std::string_view> choices) const {
  const std::string s = string();
  for (auto c : choices) {
    if (s == c)
      return s;
  }
  std::string list;
  for (auto c : choices)
    list += (list.empty() ? "\"" : ", \"") + std::string(c) + "\"";
  fail("\"" + s + "\" is not one of " + list);
}

std::vector<Node> Node::array(std::size_t min_size, std::size_t max_size) const {
  if (!value_->is_array())
    fail("expected an array, found " + type_name(*value_));
  if (value_->size() < min_size || value_->size() > max_size) {
    fail(fmt::format("expected {} to {} elements, found {}", min_size, max_size, value_->size()));
  }
  std::vector<Node> out;
  for (std::size_t i = 0; i < value_->size(); ++i) {
    out.emplace_back((*value_)[i], path_ + "/" + std::to_string(i), *file_);
  }
  return out;
}

void Node::expect_object(std::string_view what) const {
  if (!value_->is_object()) {
    fail("expected " + std::string(what) + " (an object), found " + type_name(*value_));
  }
}

bool Node::has(std::string_view key) const {
  return value_->is_object() && value_->contains(std::string(key));
}

Node Node::member(std::string_view key) const {
  return Node((*value_)[std::string(key)], path_ + "/" + escape_pointer_token(key), *file_);
}

Node Node::required(std::string_view key) {
  seen_.insert(std::string(key));
  if (!has(key)) {
    // A misspelled required key would otherwise only read as "missing": point at it.
    std::vector<std::string> present;
    if (value_->is_object()) {
      for (auto it = value_->begin(); it != value_->end(); ++it)
        present.push_back(it.key());
    }
    const std::string near = suggestion(key, present);
    Node(*value_, path_ + "/" + escape_pointer_token(key), *file_)
        .fail("missing required field \"" + std::string(key) + "\"" +
              (near.empty() ? std::string() : " (found \"" + near + "\": misspelled?)"));
  }
  return member(key);
}

std::optional<Node> Node::optional(std::string_view key) {
  seen_.insert(std::string(key));
  if (!has(key))
    return std::nullopt;
  return member(key);
}

double Node::number_or(std::string_view key, double fallback, double min, double max) {
  const auto n = optional(key);
  return n ? n->number(min, max) : fallback;
}

void Node::finish(const std::vector<std::pair<std::string, std::string>>& why_not) const {
  if (!value_->is_object())
    return;
  std::vector<std::string> known(seen_.begin(), seen_.end());
  for (auto it = value_->begin(); it != value_->end(); ++it) {
    if (seen_.count(it.key()))
      continue;
    const Node bad = member(it.key());
    for (const auto& [key, reason] : why_not) {
      if (key == it.key())
        bad.fail("field \"" + key + "\" is not allowed here: " + reason);
    }
    const std::string near = suggestion(it.key(), known);
    bad.fail("unknown field \"" + it.key() + "\"" +
             (near.empty() ? std::string() : "; did you mean \"" + near + "\"?"));
  }
}

}  // namespace tb::scenario::detail
