#include "common/map/opendrive/geo_reference.hpp"

#include <proj.h>

#include <cmath>
#include <sstream>

#include "common/map/opendrive/road_network.hpp"

namespace tb::map::odr {

namespace {

constexpr const char* kPath = "header/geoReference";

std::vector<std::string> tokens(const std::string& s) {
  std::istringstream in(s);
  std::vector<std::string> out;
  for (std::string t; in >> t;)
    out.push_back(t);
  return out;
}

std::string join(const std::vector<std::string>& t) {
  std::string s;
  for (const auto& x : t)
    s += (s.empty() ? "" : " ") + x;
  return s;
}

bool has_key(const std::vector<std::string>& t, const std::string& key) {
  for (const auto& x : t) {
    if (x == key || x.rfind(key + "=", 0) == 0)
      return true;
  }
  return false;
}

}  // namespace

struct GeoReference::Impl {
  PJ_CONTEXT* ctx = nullptr;
  PJ* pj = nullptr;  ///< map CRS -> EPSG:4979, normalised to lon, lat order
  ~Impl() {
    if (pj != nullptr)
      proj_destroy(pj);
    if (ctx != nullptr)
      proj_context_destroy(ctx);
  }
};

GeoReference::GeoReference(const std::string& proj, const std::string& source)
    : impl_(std::make_unique<Impl>()) {
  std::vector<std::string> t = tokens(proj);
  if (t.empty())
    throw MapError(source, kPath, "empty PROJ string");
  if (!has_key(t, "+proj")) {
    t.insert(t.begin(), "+proj=tmerc");
    notes_.push_back("geoReference without +proj read as +proj=tmerc at its +lat_0/+lon_0");
  }
  if (!has_key(t, "+ellps") && !has_key(t, "+datum") && !has_key(t, "+a") && !has_key(t, "+R")) {
    t.push_back("+ellps=WGS84");
  }
  if (!has_key(t, "+type"))
    t.push_back("+type=crs");
  impl_->ctx = proj_context_create();
  proj_log_level(impl_->ctx, PJ_LOG_NONE);
  auto make = [&](const std::vector<std::string>& toks) -> PJ* {
    PJ* src = proj_create(impl_->ctx, join(toks).c_str());
    if (src == nullptr)
      return nullptr;
    PJ* dst = proj_create(impl_->ctx, "EPSG:4979");
    PJ* op = dst != nullptr ? proj_create_crs_to_crs_from_pj(impl_->ctx, src, dst, nullptr, nullptr)
                            : nullptr;
    proj_destroy(src);
    if (dst != nullptr)
      proj_destroy(dst);
    if (op == nullptr)
      return nullptr;
    PJ* norm = proj_normalize_for_visualization(impl_->ctx, op);
    proj_destroy(op);
    if (norm == nullptr)
      return nullptr;
    PJ_COORD c = proj_coord(0, 0, 0, 0);
    c = proj_trans(norm, PJ_FWD, c);
    if (!std::isfinite(c.lpzt.lam) || !std::isfinite(c.lpzt.phi) || !std::isfinite(c.lpzt.z) ||
        c.lpzt.lam == HUGE_VAL) {
      proj_destroy(norm);
      return nullptr;
    }
    return norm;
  };
  impl_->pj = make(t);
  if (impl_->pj == nullptr && has_key(t, "+geoidgrids")) {
    std::vector<std::string> kept;
    std::string dropped;
    for (const auto& x : t) {
      if (x.rfind("+geoidgrids", 0) == 0) {
        dropped = x;
      } else {
        kept.push_back(x);
      }
    }
    impl_->pj = make(kept);
    if (impl_->pj != nullptr) {
      notes_.push_back("geoReference: " + dropped +
                       " not installed, ignored (heights are the map's z above the ellipsoid)");
      t = kept;
    }
  }
  if (impl_->pj == nullptr) {
    const int err = proj_context_errno(impl_->ctx);
    throw MapError(source, kPath,
                   "unreadable PROJ string '" + proj + "'" +
                       (err != 0 ? std::string(": ") + proj_context_errno_string(impl_->ctx, err)
                                 : std::string(": it does not map the origin to WGS84")));
  }
  definition_ = join(t);
}

GeoReference::~GeoReference() = default;
GeoReference::GeoReference(GeoReference&&) noexcept = default;
GeoReference& GeoReference::operator=(GeoReference&&) noexcept = default;

geodesy::Geodetic GeoReference::to_wgs84(double x, double y, double z) const {
  const PJ_COORD c = proj_trans(impl_->pj, PJ_FWD, proj_coord(x, y, z, 0));
  return {c.lpzt.phi, c.lpzt.lam, c.lpzt.z};
}

void GeoReference::from_wgs84(const geodesy::Geodetic& g, double& x, double& y, double& z) const {
  const PJ_COORD c =
      proj_trans(impl_->pj, PJ_INV, proj_coord(g.longitude_deg, g.latitude_deg, g.altitude_m, 0));
  x = c.xyz.x;
  y = c.xyz.y;
  z = c.xyz.z;
}

}  // namespace tb::map::odr
