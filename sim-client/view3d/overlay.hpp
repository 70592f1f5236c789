#pragma once
/// @file The operator's picture of the V2X network over the world (what no driving simulator
/// shows): each station's communication range as a ring on the ground, a line from each station
/// to every neighbour whose CAM it received in the last second, a red marker over each car with
/// an active LCRW warning and a yellow arrow from it to the car it is warned about, an orange
/// pylon at each DENM event position in force with its relevance area as a translucent disc,
/// and every car's station id. Toggled with a key; drawn in the main view only (not in the
/// mirror).
///
/// Shapes on the ground (rings, relevance areas) lie flat at the height of the car they belong
/// to (an event: the car nearest to it, the DENM carries no altitude), lifted 0.25 m, drawn after
/// the world with depth tests but no depth writes and a polygon offset, so that they never fight
/// the road or the ground; where a hill rises over them the rings still show faintly (a second
/// pass without depth test at 30 % opacity), so a range stays readable on any terrain.

#include <cstdint>
#include <map>
#include <string>

#include <osg/Geode>
#include <osg/Geometry>
#include <osg/Group>
#include <osg/ref_ptr>
#include <osgText/Font>
#include <osgText/Text>

#include "sim-client/view3d/frame_input.hpp"

namespace tb::client::view3d {

class V2xOverlay {
 public:
  V2xOverlay();
  osg::Group* node() const { return root_.get(); }
  void update(const FrameInput& in);

  // What is drawn now (tests).
  std::size_t links() const { return links_; }
  std::size_t markers() const { return markers_; }
  std::size_t denms() const { return denms_; }
  std::size_t range_rings() const { return rings_n_; }
  std::size_t warning_lines() const { return warnings_; }
  std::size_t denm_areas() const { return areas_n_; }

  /// Lift of the ground shapes over the height of their car or event, m.
  static constexpr float kGroundLift = 0.25f;
  /// Height of the warning arrows over the cars' roofs, m.
  static constexpr float kWarningOverRoof = 0.5f;

 private:
  osgText::Text* label(const std::string& key);
  osg::ref_ptr<osg::Group> root_;
  osg::ref_ptr<osg::Geode> geode_;
  struct Layer {
    explicit Layer(GLenum mode);
    void clear();
    void commit();
    osg::ref_ptr<osg::Vec3Array> v;
    osg::ref_ptr<osg::Vec4Array> c;
    osg::ref_ptr<osg::DrawArrays> d;
    osg::ref_ptr<osg::Geometry> g;
  };
  Layer lines_, solids_, warn_, rings_, areas_;
  osg::ref_ptr<osgText::Font> font_;
  std::map<std::string, osg::ref_ptr<osgText::Text>> labels_;
  std::size_t links_ = 0, markers_ = 0, denms_ = 0, rings_n_ = 0, warnings_ = 0, areas_n_ = 0;
};

}  // namespace tb::client::view3d
