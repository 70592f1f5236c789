// Writes the fuzz seed corpora (tests/fuzz/cam, denm, spatem, mapem) from the sample messages, so
// that the committed seeds stay the encodings of the golden and boundary samples.
// Usage: its_messages_write_seeds <repository root>

#include <filesystem>
#include <fstream>
#include <iostream>
#include <string>
#include <vector>

#include "its-station/messages/tests/samples.hpp"
#include "its-station/messages/tests/signal_samples.hpp"

namespace {

bool write(const std::filesystem::path& path, const std::vector<std::uint8_t>& bytes) {
  std::ofstream out(path, std::ios::binary);
  out.write(reinterpret_cast<const char*>(bytes.data()),
            static_cast<std::streamsize>(bytes.size()));
  return out.good();
}

}  // namespace

tb::its::messages::Cam as_version1(tb::its::messages::Cam m) {
  m.header.protocolVersion = tb::its::messages::kProtocolVersion1;
  return m;
}
using tb::its::messages::samples::as_version1;

int main(int argc, char** argv) {
  using namespace tb::its::messages;
  if (argc != 2) {
    std::cerr << "usage: " << argv[0] << " <repository root>\n";
    return 2;
  }
  const std::filesystem::path root = argv[1];
  const std::pair<const char*, Cam> cams[] = {
      {"cam_hf.uper", samples::cam_hf()},
      {"cam_rsu.uper", samples::cam_rsu()},
      {"cam_lf.uper", samples::cam_lf()},
      {"cam_path20.uper", samples::cam_with_path(20)},
      {"cam_upper.uper", samples::cam_at_bounds(true)},
      {"cam_lower.uper", samples::cam_at_bounds(false)},
      {"cam_v1.uper",
       [] {
         Cam c = as_version1(samples::cam_at_bounds(true));
         (*vehicle_hf(c.cam.camParameters)).curvature.curvatureValue = -30000;
         return c;
       }()},
  };
  const std::pair<const char*, Denm> denms[] = {
      {"denm_collision_risk.uper", samples::denm_collision_risk()},
      {"denm_upper.uper", samples::denm_at_bounds(true)},
      {"denm_lower.uper", samples::denm_at_bounds(false)},
      {"denm_v1.uper", as_version1(samples::denm_collision_risk())},
      {"denm_v1_upper.uper", as_version1(samples::denm_at_bounds(true))},
      {"denm_alacarte.uper",
       [] {
         Denm d = samples::denm_collision_risk();
         d.denm.alacarte = samples::alacarte_full();
         return d;
       }()},
  };
  bool ok = true;
  for (const auto& [name, cam] : cams) {
    auto bytes = encode(cam);
    ok = ok && bytes && write(root / "tests/fuzz/cam" / name, *bytes);
  }
  const auto special = samples::cams_special_vehicle();
  for (std::size_t i = 0; i < special.size(); ++i) {
    auto bytes = encode(special[i]);
    ok = ok && bytes &&
         write(root / "tests/fuzz/cam" / ("cam_special" + std::to_string(i) + ".uper"), *bytes);
  }
  for (const auto& [name, denm] : denms) {
    auto bytes = encode(denm);
    ok = ok && bytes && write(root / "tests/fuzz/denm" / name, *bytes);
  }
  // SPATEM and MAPEM: the worked examples, the typical junction, the lower bounds and every
  // optional component and alternative (not the largest messages: their hundreds of kilobytes
  // would make every fuzz input that long).
  const std::pair<const char*, std::unique_ptr<Spatem>> spatems[] = {
      {"spatem_two_groups.uper", samples::spatem_two_groups()},
      {"spatem_typical.uper", samples::spatem_typical()},
      {"spatem_lower.uper", samples::spatem_at_bounds(false)},
      {"spatem_every_optional.uper", samples::spatem_every_optional()},
  };
  for (const auto& [name, m] : spatems) {
    auto bytes = encode(*m);
    ok = ok && bytes && write(root / "tests/fuzz/spatem" / name, *bytes);
  }
  const std::pair<const char*, std::unique_ptr<Mapem>> mapems[] = {
      {"mapem_one_lane.uper", samples::mapem_one_lane()},
      {"mapem_typical.uper", samples::mapem_typical()},
      {"mapem_lower.uper", samples::mapem_at_bounds(false)},
      {"mapem_every_optional.uper", samples::mapem_every_optional()},
  };
  for (const auto& [name, m] : mapems) {
    auto bytes = encode(*m);
    ok = ok && bytes && write(root / "tests/fuzz/mapem" / name, *bytes);
  }
  if (!ok) {
    std::cerr << "cannot write the seeds under " << root << "\n";
    return 1;
  }
  return 0;
}
