#pragma once
/// @file Loading and validating scenario files.

#include <cstddef>
#include <filesystem>
#include <optional>
#include <stdexcept>
#include <string>
#include <string_view>

#include "common/scenario/scenario.hpp"

namespace tb::scenario {

/// Programs exit with this code when the scenario cannot be used.
inline constexpr int kExitBadScenario = 2;

/// A scenario that cannot be used. what() reads "FILE: /json/pointer: reason".
class ScenarioError : public std::runtime_error {
 public:
  ScenarioError(std::string file, std::string path, std::string reason);
  const std::string& file() const { return file_; }
  /// JSON pointer of the offending field (RFC 6901), "" for the whole document.
  const std::string& path() const { return path_; }
  const std::string& reason() const { return reason_; }

 private:
  std::string file_, path_, reason_;
};

/// Largest OpenDRIVE file a scenario may name (sim-server hands the text to its clients).
inline constexpr std::size_t kMaxMapBytes = 32u << 20;

/// Reads and validates a scenario file, and the OpenDRIVE file its map names (relative to the
/// scenario file's folder). @throws ScenarioError.
Scenario load_file(const std::filesystem::path& file);
/// Validates scenario JSON text; @p file_name labels messages and is where a relative map file
/// is looked for. @p map_text, when given, is the OpenDRIVE map's text in place of the file
/// (a sim-client gets it from the server's Welcome). @throws ScenarioError.
Scenario parse(std::string_view json_text, const std::string& file_name,
               std::optional<std::string_view> map_text = std::nullopt);

}  // namespace tb::scenario
