#pragma once
/// @file The joints between the layers of the station, which sit above all of them (so that no
/// layer depends upwards): positions for the GN router, the facilities' sender over BTP, the
/// applications' DEN port over the DEN service, and the MQTT views of facilities data.

#include <optional>

#include "common/clock/clock.hpp"

#include "its-station/apps/den/den_port.hpp"
#include "its-station/apps/lcrw/lcrw.hpp"
#include "its-station/apps/mqtt/messages.hpp"
#include "its-station/btp/dispatcher.hpp"
#include "its-station/facilities/den_service.hpp"
#include "its-station/facilities/ldm.hpp"
#include "its-station/facilities/position.hpp"
#include "its-station/facilities/transport.hpp"
#include "its-station/facilities/vehicle_data.hpp"
#include "its-station/geonet/position_provider.hpp"

namespace tb::its::station {

/// The router's ego position vector from the station's newest fix.
class GnPositionAdapter final : public geonet::PositionProvider {
 public:
  /// itsGnPaiInterval (EN 302 636-4-1 Annex H): 80 m.
  static constexpr double kPaiIntervalM = 80.0;
  explicit GnPositionAdapter(const facilities::PositionProvider& p) : position_(p) {}
  std::optional<geonet::EgoPosition> current_position() const override;

 private:
  const facilities::PositionProvider& position_;
};

/// CAMs as SHB and DENMs as GBC, both BTP-B (EN 302 636-5-1).
class BtpMessageSender final : public facilities::MessageSender {
 public:
  /// CAMs go with traffic class 2 and a GN lifetime of 1 s, as C2C-CC vehicles send them (DCC
  /// profile DP2 of TS 102 636-4-2: periodic awareness); the lifetime bounds nothing for SHB.
  static constexpr geonet::TrafficClass kCamTrafficClass{false, false, 2};
  static constexpr clock::Duration kCamLifetime = std::chrono::seconds{1};
  /// DENMs go with the traffic class ID the DEN service asks for (facilities::DenRequest:
  /// 1, or 0 for time-critical warnings), without store-carry-forward, so that a GBC at a
  /// greedy local optimum is broadcast.

  explicit BtpMessageSender(btp::Dispatcher& btp) : btp_(btp) {}
  facilities::SendResult send_single_hop(std::uint16_t port,
                                         std::span<const std::uint8_t> payload) override;
  facilities::SendResult send_geobroadcast(std::uint16_t port, const facilities::GeoArea& area,
                                           std::span<const std::uint8_t> payload,
                                           std::uint32_t lifetime_ms,
                                           std::uint8_t traffic_class) override;

 private:
  btp::Dispatcher& btp_;
};

facilities::SendResult to_send_result(geonet::DataConfirm c);

/// What the DEN service learns of a received DENM from GeoNetworking: its destination area
/// (GBC) and traffic class ID; a packet that came without GN indication gives the defaults.
facilities::DenmReception den_reception(const btp::Indication& ind);

/// Whether the station stands in an area: GeoNetworking's geometric function (EN 302 931) at
/// the newest fix; without a fix it counts as inside.
class GnAreaLocator final : public facilities::AreaLocator {
 public:
  explicit GnAreaLocator(const facilities::PositionProvider& p) : position_(p) {}
  bool inside(const facilities::GeoArea& area) const override;

 private:
  const facilities::PositionProvider& position_;
};

/// The applications' DEN port over the facilities' DEN service. The destination area is a
/// circle around the event as large as its relevance distance class.
class DenPortAdapter final : public apps::DenService {
 public:
  DenPortAdapter(facilities::DenService& den, clock::Duration repetition_interval,
                 clock::Duration repetition_duration)
      : den_(den), interval_(repetition_interval), duration_(repetition_duration) {}
  std::optional<apps::ActionId> trigger(const apps::DenEventRequest& request) override;
  bool update(const apps::ActionId& id, const apps::DenEventRequest& request) override;
  bool terminate(const apps::ActionId& id) override;

  facilities::DenRequest to_request(const apps::DenEventRequest& r) const;

 private:
  facilities::DenService& den_;
  clock::Duration interval_;
  clock::Duration duration_;
};

/// Views for LCRW and MQTT.
apps::mqtt::Kinematics own_kinematics(const facilities::PositionFix& fix,
                                      const facilities::VehicleData* vehicle,
                                      std::optional<double> length_m,
                                      std::optional<double> width_m);
apps::mqtt::Kinematics neighbour_kinematics(const facilities::Neighbour& n);
apps::mqtt::DenmView denm_view(const messages::Denm& d);
/// LCRW's view: positions in the local frame, the CAM reference point (front centre) moved to
/// the bounding-box centre.
apps::VehicleKinematics lcrw_kinematics(std::uint32_t station_id, const apps::mqtt::Kinematics& k,
                                        clock::WallTime time, const geodesy::LocalFrame& frame);

}  // namespace tb::its::station
