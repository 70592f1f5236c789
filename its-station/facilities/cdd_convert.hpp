#pragma once
/// @file SI values ⇄ the integer units of the ETSI common data dictionary (TS 102 894-2
/// V1.3.1), with its rounding, clamping and "outOfRange"/"unavailable" rules.

#include <optional>

#include "its-station/facilities/position.hpp"
#include "its-station/messages/cdd.hpp"

namespace tb::its::facilities::cdd {

namespace m = tb::its::messages;

m::Latitude latitude(double deg);
m::Longitude longitude(double deg);
/// Empty for the "unavailable" values.
std::optional<double> latitude_deg(m::Latitude v);
std::optional<double> longitude_deg(m::Longitude v);

m::PosConfidenceEllipse confidence_ellipse(const std::optional<PositionFix::Ellipse>& e);
m::Altitude altitude(std::optional<double> metres, std::optional<double> confidence_m);
m::ReferencePosition reference_position(const PositionFix& fix);

m::HeadingValue heading_value(std::optional<double> deg);
std::optional<double> heading_deg(m::HeadingValue v);
m::HeadingConfidence heading_confidence(std::optional<double> deg);
m::Heading heading(std::optional<double> deg, std::optional<double> confidence_deg);

m::SpeedValue speed_value(std::optional<double> mps);
std::optional<double> speed_mps(m::SpeedValue v);
m::SpeedConfidence speed_confidence(std::optional<double> mps);

m::AccelerationValue acceleration_value(std::optional<double> mps2);
m::YawRate yaw_rate(std::optional<double> dps);
m::SteeringWheelAngle steering_wheel_angle(std::optional<double> deg);
/// Curvature from yaw rate and speed (κ = ω / v), CurvatureCalculationMode yawRateUsed.
m::Curvature curvature(std::optional<double> yaw_rate_dps, std::optional<double> speed_mps);

/// Upper bound of a RelevanceDistance class, m (over10km: 20 km), the radius of the relevance
/// area a DENM of that class is GeoBroadcast in.
double relevance_radius_m(m::RelevanceDistance d);

}  // namespace tb::its::facilities::cdd
