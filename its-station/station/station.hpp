#pragma once
/// @file One ITS station composed from its ports: what its-station's main and station-host
/// build, once or hundreds of times in one process, and what a unit test builds without
/// sockets (its-station/README.md, "Station and its ports").

#include <array>
#include <cstdint>
#include <memory>
#include <optional>
#include <set>
#include <vector>

#include <nlohmann/json.hpp>

#include "common/clock/gnss_disciplined_runtime.hpp"
#include "common/clock/runtime.hpp"
#include "common/geodesy/local_frame.hpp"
#include "common/mqtt/sink.hpp"
#include "its-station/apps/lcrw/lcrw_app.hpp"
#include "its-station/apps/lcrw/lcrw_denm.hpp"
#include "its-station/apps/mqtt/publisher.hpp"
#include "its-station/apps/signal/signal_app.hpp"
#include "its-station/btp/dispatcher.hpp"
#include "its-station/facilities/ca_service.hpp"
#include "its-station/facilities/den_service.hpp"
#include "its-station/facilities/intersection_receiver.hpp"
#include "its-station/facilities/ldm.hpp"
#include "its-station/facilities/position.hpp"
#include "its-station/facilities/reference_position.hpp"
#include "its-station/facilities/vehicle_data.hpp"
#include "its-station/geonet/router.hpp"
#include "its-station/link/link_layer.hpp"
#include "its-station/security/security_entity.hpp"
#include "its-station/station/adapters.hpp"
#include "its-station/station/station_config.hpp"
#include "its-station/station/time_synced_link.hpp"

namespace tb::its::station {

/// What a station is built from. Every port outlives the Station and delivers (fixes, frames,
/// timers) on one thread, the caller's. The position provider keeps its listeners (it has no
/// way to drop them), so it must deliver no fix after the Station is gone; the link's handler
/// is removed when the Station goes.
struct StationPorts {
  /// Timers, the host's monotonic and wall time (sockets, MQTT, trace records).
  clock::Runtime& runtime;
  /// The station's ITS clock over @c runtime: the Station disciplines it from its fixes.
  clock::GnssDisciplinedRuntime& its_clock;
  /// The receiver's raw fixes (at the antenna, course over ground).
  facilities::PositionProvider& gnss;
  /// The vehicle's signals; null: none (no CAN).
  facilities::VehicleDataProvider* vehicle_data = nullptr;
  /// The radio.
  link::LinkLayer& link;
  /// Signs and verifies (TS 103 097); null: unsecured packets only.
  security::SecurityEntity* security = nullptr;
  /// Where the station mirrors its state, received CAMs and DENMs and LCRW warnings; null: no
  /// MQTT.
  tb::mqtt::MqttSink* mqtt = nullptr;
};

/// Tells the ITS clock of each fix before anything else hears of it (docs/time.md), and says in
/// the log when it first synchronises and when GNSS time jumps.
class ItsClockDiscipline {
 public:
  ItsClockDiscipline(facilities::PositionProvider& position, clock::GnssDisciplinedRuntime& its,
                     const clock::Clock& host);
};

/// The stack between the ports: reference position, GeoNetworking and BTP, LDM, CA and DEN
/// services, MAPEM/SPATEM reception, LCRW, the signal application (RLVW, GLOSA), the MQTT
/// mirror, and the status an operator reads.
class Station {
 public:
  Station(const StationPorts& ports, StationConfig config);
  ~Station();
  Station(const Station&) = delete;
  Station& operator=(const Station&) = delete;

  /// Starts the CA service (CAMs as fixes make them due) and says so in the log.
  void start();
  /// Stops sending CAMs and evaluating LCRW at predicted onsets.
  void stop();

  /// Decode received CAMs through @p decoder, shared with the other stations of this thread
  /// (station-host's pooled stations): one decoded CAM per frame for all of them (issue 33).
  void share_cam_decoder(facilities::SharedCamDecoder& decoder) {
    ca_.set_shared_decoder(&decoder);
  }
  /// Likewise one parse of each frame's GN headers for all of them.
  void share_packet_parser(geonet::SharedPacketParser& parser) {
    router_.set_shared_parser(&parser);
  }

  /// The LDM as the station sees it, its counters and, when it verifies, what it refused:
  /// what its-station writes to --status-file. A refusal the station had not reported before is
  /// also said once in the log (a station of another PKI: untrusted_root).
  nlohmann::json status();
  /// The totals its-station logs when it ends.
  void log_totals() const;

  const StationConfig& config() const { return config_; }
  const facilities::PositionProvider& position() const { return position_; }
  const facilities::Ldm& ldm() const { return ldm_; }
  const facilities::CaService& ca() const { return ca_; }
  const facilities::DenService& den() const { return den_; }
  const geonet::Router& router() const { return router_; }
  /// BTP-B over GN as the services send (a road-side unit's MAPEM/SPATEM service, issue 34).
  facilities::MessageSender& sender() { return sender_; }
  /// Null until LCRW first ran (it starts at the first fix).
  const apps::LcrwApplication* lcrw() const { return lcrw_.get(); }
  /// Null unless the station runs the signal application (StationConfig::signals).
  const apps::signal::SignalApplication* signal_app() const { return signal_app_.get(); }
  const facilities::IntersectionReceiver* intersection_receiver() const {
    return intersection_rx_.get();
  }

 private:
  void receive_cam(const btp::Indication& ind, std::span<const std::uint8_t> payload);
  void mirror_to_mqtt();
  apps::mqtt::Kinematics own_state(const facilities::PositionFix& fix) const;
  void on_fix(const facilities::PositionFix& fix);
  void evaluate_lcrw(const facilities::PositionFix& fix, const apps::mqtt::Kinematics& own,
                     std::optional<std::uint32_t> cam_from);
  void on_lcrw_warning(const apps::LcrwWarning& w);
  void schedule_onset(std::optional<double> onset_s);
  void cancel_onset();
  void start_signal_app();
  void update_signal_app(const facilities::PositionFix& fix, const apps::mqtt::Kinematics& own);
  void on_intersection_map(const facilities::IntersectionEntry& e);
  void on_intersection_spat(const facilities::IntersectionEntry& e);
  void on_rlvw(const apps::signal::RlvwWarning& w);
  nlohmann::json signals_status() const;

  clock::Runtime& runtime_;
  clock::GnssDisciplinedRuntime& its_clock_;
  facilities::VehicleDataProvider* vehicle_data_;
  security::SecurityEntity* security_;
  StationConfig config_;

  facilities::ReferencePositionProvider position_;
  ItsClockDiscipline clock_discipline_;  // before every other listener of position_
  GnPositionAdapter gn_position_;
  TimeSyncedLink synced_link_;
  geonet::Router router_;
  btp::Dispatcher btp_;
  BtpMessageSender sender_;
  facilities::Ldm ldm_;
  facilities::CaService ca_;
  GnAreaLocator den_locator_;
  facilities::DenService den_;
  std::unique_ptr<apps::mqtt::StationPublisher> publisher_;
  DenPortAdapter den_port_;

  // LCRW, made at the first fix (its frame may need that fix).
  std::optional<geodesy::LocalFrame> frame_;
  std::unique_ptr<apps::LcrwDenmTrigger> lcrw_denm_;
  std::unique_ptr<apps::LcrwApplication> lcrw_;
  std::set<std::uint32_t> published_about_;  // neighbours of the current evaluation's warnings
  // The neighbours an evaluation assesses, kept between evaluations: one runs at every CAM
  // received (150 a second at 49 neighbours), and a vector per evaluation was an allocation each.
  std::vector<apps::VehicleKinematics> lcrw_others_;
  std::optional<clock::TimerId> onset_timer_;
  bool stopped_ = false;

  // The signal application (issue 34), made when the vehicle runs it.
  std::unique_ptr<facilities::IntersectionReceiver> intersection_rx_;
  std::unique_ptr<apps::signal::SignalApplication> signal_app_;
  std::uint64_t rlvw_raised_ = 0;
  // (intersection, revision) whose refusal the log has said, so that a bad MAPEM at 1 Hz is
  // reported once.
  std::set<std::pair<std::uint16_t, std::uint8_t>> refused_maps_said_;

  std::array<bool, static_cast<std::size_t>(security::VerifyResult::kCount)> refusals_said_{};
};

}  // namespace tb::its::station
