#pragma once
/// @file Cooperative Awareness basic service, EN 302 637-2 V1.4.1: generates the station's CAMs
/// from its fixes and vehicle data, and hands received CAMs to the LDM.

#include <cstdint>
#include <functional>
#include <span>

#include "common/clock/runtime.hpp"
#include "its-station/facilities/cam_rules.hpp"
#include "its-station/facilities/ldm.hpp"
#include "its-station/facilities/path_history.hpp"
#include "its-station/facilities/position.hpp"
#include "its-station/facilities/shared_cam_decoder.hpp"
#include "its-station/facilities/transport.hpp"
#include "its-station/facilities/vehicle_data.hpp"
#include "its-station/messages/cam.hpp"

namespace tb::its::facilities {

struct CaConfig {
  messages::StationID station_id = 0;
  messages::StationType station_type = messages::station_type::kPassengerCar;
  CamTiming timing;
  scenario::CamPolicy policy;  ///< the standard's rules by default; `fixed` for the thesis
  std::optional<double> vehicle_length_m;
  std::optional<double> vehicle_width_m;
  /// The vehicle's role (scenario "role"): in the low-frequency container, and the
  /// special-vehicle container of the roles that have one.
  messages::VehicleRole vehicle_role = messages::VehicleRole::default_;
  /// What a dangerousGoods vehicle carries (its DangerousGoodsContainer).
  std::optional<messages::DangerousGoodsBasic> dangerous_goods;
  /// Whether received CAMs are traced (its.cam_rx, its.ldm; docs/tracing.md). Off for a pooled
  /// station: 300 of them in range would write 300 × 800 records a second (issue 33). The
  /// records of the station's own CAMs stay.
  bool trace_receptions = true;
};

/// The special-vehicle container of @p config's role (EN 302 637-2 B.2.x): publicTransport,
/// specialTransport, dangerousGoods, roadWork, rescue, emergency and safetyCar each have one,
/// the other roles none (empty). lightBarSirenInUse comes from @p vehicle's light bar and siren
/// where the container has it (both off when the vehicle data does not say); the optional
/// components the station cannot know (ptActivation, incidentIndication, emergencyPriority,
/// closedLanes …) are left out.
std::optional<messages::SpecialVehicleContainer> special_vehicle_container(
    const CaConfig& config, const VehicleData* vehicle);

/// Builds the CAM of @p fix (reference position, heading, speed and generationDeltaTime all
/// from the fix, so the CAM names the fix it came from), with @p vehicle's signals; with the
/// low-frequency container when @p low_frequency_path is given, and the special-vehicle
/// container of the station's role when @p with_special_vehicle.
messages::Cam build_cam(const CaConfig& config, const PositionFix& fix, const VehicleData* vehicle,
                        const messages::PathHistory* low_frequency_path,
                        bool with_special_vehicle = false);

/// The generation policy the service runs: @p config's, except for a road-side unit
/// (station type 15), which sends at a fixed T_GenCamMax interval (EN 302 637-2 clause 6.1.4).
scenario::CamPolicy effective_policy(const CaConfig& config);

class CaService {
 public:
  struct Counters {
    std::uint64_t sent = 0;
    std::uint64_t suppressed_no_fix = 0;  ///< generation checks that found no fix
    std::uint64_t encode_errors = 0;
    std::uint64_t send_errors = 0;
    std::uint64_t received = 0;
    std::uint64_t decode_errors = 0;
    std::uint64_t own_dropped = 0;  ///< our own CAMs heard back
    /// Signed CAMs whose content their signer's SSP does not permit (ssp_permissions.hpp).
    std::uint64_t not_permitted = 0;
  };
  /// Called for each CAM handed to the network: the CAM, why, the fix it came from.
  using SentListener = std::function<void(const messages::Cam&, CamTrigger, const PositionFix&)>;

  /// @p vehicle may be null (no CAN data: vehicle fields are "unavailable").
  CaService(clock::Runtime& runtime, PositionProvider& position, VehicleDataProvider* vehicle,
            MessageSender& sender, Ldm& ldm, CaConfig config);
  ~CaService();
  CaService(const CaService&) = delete;
  CaService& operator=(const CaService&) = delete;

  void start();
  void stop();

  /// A BTP-B packet for port 2001 arrived. @p ssp: the signer AT's CAM SSP of a CAM that came
  /// signed and verified, checked against its content; none for an unsecured CAM.
  void receive(std::span<const std::uint8_t> payload, clock::WallTime rx_time,
               std::optional<std::span<const std::uint8_t>> ssp = std::nullopt);

  /// Decode received CAMs through @p decoder (shared by the services of one thread, which then
  /// keep one decoded CAM per frame between them); null: each CAM decoded on its own.
  /// The LDM then caches its neighbours in the decoder's SenderIndex. Before the first CAM.
  void set_shared_decoder(SharedCamDecoder* decoder);

  void on_sent(SentListener l) { sent_listeners_.push_back(std::move(l)); }
  const Counters& counters() const { return counters_; }
  const CamRules& rules() const { return rules_; }

 private:
  /// Clause 6.1.3 at this instant: on every fix, and from the timer schedule_check() sets.
  void check();
  /// Whether a time-based CAM due now may be made from @p fix (not one a fix period old).
  bool fix_fits_time_cam(const PositionFix& fix, clock::SteadyTime now) const;
  /// Whether @p fix arrived at (or just before, CamTiming::fresh_fix_wait) the instant the next
  /// time-based CAM falls due, or after it; true before the first CAM.
  bool fix_of_due_instant(const PositionFix& fix) const;
  void generate(CamTrigger why, const PositionFix& fix);
  void schedule_check();

  clock::Runtime& runtime_;
  PositionProvider& position_;
  VehicleDataProvider* vehicle_;
  MessageSender& sender_;
  Ldm& ldm_;
  CaConfig config_;
  CamRules rules_;
  PathHistoryRecorder path_;
  Counters counters_;
  std::vector<SentListener> sent_listeners_;
  SharedCamDecoder* decoder_ = nullptr;
  clock::TimerId check_timer_ = 0;
  bool running_ = false;
  bool reported_no_fix_ = false;
};

}  // namespace tb::its::facilities
