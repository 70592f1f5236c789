#pragma once
/// @file How far a frame gets under a scenario's channel model: the path loss the network
/// emulator's radio medium applies (network-emulator/radio/channel.hpp) and the distance at
/// which it stops delivering. One definition, so that the operator's view draws the range the
/// medium enforces.

#include <optional>

#include "common/scenario/scenario.hpp"

namespace tb::scenario {

/// Path loss in dB at @p distance_m for the log-distance or two-ray model; distances below 1 m
/// count as 1 m (the reference distance). Not defined for ideal and range.
double path_loss_db(const ChannelModel& m, double distance_m);

/// The largest distance at which the channel still delivers a frame (before its random packet
/// errors): range_m for the range model, where the received power falls to the sensitivity for
/// the path-loss models. Empty for the ideal model (every frame arrives, however far).
std::optional<double> max_range_m(const ChannelModel& m);

}  // namespace tb::scenario
