#pragma once
/// @file Strict reading of JSON objects: types, ranges, required fields and unknown keys.
/// Internal to the scenario loader.

#include <nlohmann/json.hpp>

#include <initializer_list>
#include <optional>
#include <set>
#include <string>
#include <string_view>
#include <vector>

#include "common/scenario/loader.hpp"

namespace tb::scenario::detail {

/// A JSON value with its JSON-pointer path. Every error it raises is a ScenarioError naming
/// the file, the path and the reason.
class Node {
 public:
  Node(const nlohmann::json& value, std::string path, const std::string& file)
      : value_(&value), path_(std::move(path)), file_(&file) {}

  const std::string& path() const { return path_; }
  const nlohmann::json& json() const { return *value_; }
  [[noreturn]] void fail(const std::string& reason) const;

  // --- typed reads of this value -------------------------------------------------------------
  double number(double min, double max) const;
  long long integer(long long min, long long max) const;
  std::string string() const;
  bool boolean() const;
  /// One of @p choices; the error lists them.
  std::string choice(std::initializer_list<std::string_view> choices) const;
  std::vector<Node> array(std::size_t min_size, std::size_t max_size) const;
  bool is_object() const { return value_->is_object(); }
  bool is_string() const { return value_->is_string(); }

  // --- object members ------------------------------------------------------------------------
  /// Checks that this value is an object; @p what names it in the error.
  void expect_object(std::string_view what) const;
  bool has(std::string_view key) const;
  Node required(std::string_view key);
  std::optional<Node> optional(std::string_view key);
  double number_or(std::string_view key, double fallback, double min, double max);
  /// Marks keys as known but read elsewhere.
  void accept(std::string_view key) { seen_.insert(std::string(key)); }
  /// Rejects every member that was not read: a misspelled key is an error, never ignored.
  /// @p why_not explains keys that exist elsewhere but not here (for example "only with
  /// model noisy").
  void finish(const std::vector<std::pair<std::string, std::string>>& why_not = {}) const;

 private:
  Node member(std::string_view key) const;

  const nlohmann::json* value_;
  std::string path_;
  const std::string* file_;
  std::set<std::string> seen_;
};

/// Keys this loader knows, for "did you mean" suggestions.
std::string suggestion(std::string_view unknown, const std::vector<std::string>& known);

}  // namespace tb::scenario::detail
