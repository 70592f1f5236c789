#pragma once
/// @file The operator's picture of the V2X network over the world (what no driving simulator
/// shows): a line from each station to every neighbour whose CAM it received in the last
/// second, a red marker over each car with an active LCRW warning, an orange pylon at each
/// DENM event position in force, and every car's station id. Toggled with a key; drawn in
/// the main view only (not in the mirror).

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

 private:
  osgText::Text* label(const std::string& key);
  osg::ref_ptr<osg::Group> root_;
  osg::ref_ptr<osg::Geode> geode_;
  osg::ref_ptr<osg::Geometry> lines_, solids_;
  osg::ref_ptr<osg::Vec3Array> lv_, sv_;
  osg::ref_ptr<osg::Vec4Array> lc_, sc_;
  osg::ref_ptr<osg::DrawArrays> ld_, sd_;
  osg::ref_ptr<osgText::Font> font_;
  std::map<std::string, osg::ref_ptr<osgText::Text>> labels_;
  std::size_t links_ = 0, markers_ = 0, denms_ = 0;
};

}  // namespace tb::client::view3d
