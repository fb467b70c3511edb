// SPDX-License-Identifier: MIT
#include "app/lighting_check.hpp"

#include <sstream>

namespace vplrender {

namespace {

bool automatic(const std::string& rule) { return rule.rfind("automatic", 0) == 0; }

// What to try, from how the camera and the light were chosen.
std::string hints(const prepared_scene& p) {
  std::ostringstream h;
  h << "try ";
  if (automatic(p.camera_rule))
    h << "--camera EX,EY,EZ,TX,TY,TZ,UX,UY,UZ,FOV (the automatic camera frames the bounding sphere from +Z: "
         "for a closed room or a model seen from behind it is outside the scene, looking at the back of a wall)";
  else
    h << "--camera EX,EY,EZ,TX,TY,TZ,UX,UY,UZ,FOV to look at surfaces the light reaches";
  h << ", or --light X,Y,Z to move the light (now at (" << p.s.light.position.x << ", " << p.s.light.position.y << ", "
    << p.s.light.position.z << "), " << p.light_rule << ") where it sees what the camera sees";
  return h.str();
}

}  // namespace

std::vector<std::string> lighting_warnings(const prepared_scene& p, const options& o, const lighting_facts& f) {
  std::vector<std::string> w;
  if (f.visible_pixels == 0) {
    w.push_back("the image is black: the camera sees no geometry (every pixel is background); try --camera "
                "EX,EY,EZ,TX,TY,TZ,UX,UY,UZ,FOV to look at the scene (bounds in the 'bounds' line above)");
    return w;
  }
  if (f.directly_lit_pixels == 0) {
    std::ostringstream m;
    m << "the camera sees nothing lit: none of the " << f.visible_pixels
      << " pixels that show a surface is reached by the light directly";
    if (f.image_black) m << ", and the image is black";
    m << "; " << hints(p);
    w.push_back(m.str());
    return w;
  }
  if (f.image_black) {
    std::ostringstream m;
    m << "the image is black: " << f.directly_lit_pixels << " of " << f.visible_pixels
      << " visible pixels are lit directly, but no indirect light reaches what the camera sees";
    if (!o.direct) m << "; add --direct to see the direct light too, or " << hints(p).substr(4);
    else m << "; " << hints(p);
    w.push_back(m.str());
  }
  return w;
}

}  // namespace vplrender
