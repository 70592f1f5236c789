#pragma once
/// @file The MAPEM of one signalised junction (ETSI TS 103 301, ISO TS 19091 MapData), built
/// once from the map: the road-side unit sends the same bytes for as long as the map is the
/// same (README.md, "MAPEM from the map").

#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include "common/geodesy/georeferencing.hpp"
#include "common/map/opendrive/road_network.hpp"
#include "common/map/opendrive/signal_layout.hpp"
#include "its-station/messages/mapem.hpp"

namespace tb::its::rsu {

/// Which OpenDRIVE lane a MAPEM lane describes.
struct MappedLane {
  messages::LaneID lane_id = 0;
  bool ingress = false;  ///< ingress (a SignalApproach) or egress (a lane leaving the junction)
  int road = -1;         ///< index into RoadNetwork::roads
  int lane = 0;          ///< OpenDRIVE lane id
  /// Where the node list starts in the local frame: the stop line (ingress) or the junction
  /// end of the road (egress), m.
  double first_x = 0.0, first_y = 0.0;
};

/// One junction's MAPEM and what it was built from.
struct IntersectionMap {
  std::shared_ptr<const messages::Mapem> mapem;  ///< ~1.8 MB: kept on the heap
  std::vector<std::uint8_t> encoded;             ///< its UPER encoding, sent as it is
  std::vector<MappedLane> lanes;                 ///< ascending by LaneID
  std::uint16_t intersection_id = 0;
  messages::MsgCount revision = 0;
};

/// Tuning of the node lists; the defaults are what the RSU uses (README.md).
struct MapemOptions {
  double node_tolerance_m = 0.10;    ///< largest distance of the lane centre from the node polyline
  double max_lane_length_m = 200.0;  ///< how far upstream (downstream) a lane is described
  double sample_step_m = 0.5;        ///< the lane centre is sampled this finely first
};

/// Builds the MAPEM of a signalised junction from the road network, its signal layout and the
/// map's georeference (local frame <-> WGS84).
class MapemBuilder {
 public:
  MapemBuilder(const map::odr::RoadNetwork& net, const map::odr::SignalLayout& layout,
               const geodesy::Georeferencing& geo, MapemOptions options = {});

  /// The MAPEM of OpenDRIVE junction @p junction_id. @throws map::odr::MapError (file,
  /// `junction[@id='..']`, reason) for a junction that does not exist or has no traffic lights,
  /// more lanes or connections than a MAPEM holds, or a geometry the codec refuses.
  IntersectionMap build(const std::string& junction_id) const;

 private:
  const map::odr::RoadNetwork& net_;
  const map::odr::SignalLayout& layout_;
  const geodesy::Georeferencing& geo_;
  MapemOptions options_;
};

/// The junction's centre as the contract defines it: the mean of its connecting roads' start
/// points (x, y, and the surface z there). @throws MapError for a junction without roads.
geodesy::Enu junction_centre(const map::odr::RoadNetwork& net, std::size_t junction);

}  // namespace tb::its::rsu
