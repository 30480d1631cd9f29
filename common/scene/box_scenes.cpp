#include "scene/box_scenes.h"

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <limits>
#include <numeric>
#include <stdexcept>

#include "core/atomic_file.h"
#include "core/error.h"
#include "planning/random.h"

namespace ausbau {
namespace {

namespace fs = std::filesystem;
using Vec3 = Eigen::Vector3d;
using Vec2 = Eigen::Vector2d;
using Mat3 = Eigen::Matrix3d;

constexpr double kPi = 3.14159265358979323846;
constexpr double kDeg = kPi / 180.0;
// The files interpolate a rotation about the world origin (lerp of t, slerp
// of q). A rotation about an axis r mm from the origin then bows off the
// true motion by r * step^2 / 8 between two waypoints: under 1 micrometre at
// 5 m with this step.
constexpr double kMaxStepAngle = 1e-3;
constexpr double kFinalGap = 1.0;          // world AABB gap of D and S at the known path's end
constexpr double kMinClearance = 0.2;      // smallest designed rigid clearance, every family
constexpr double kWrongPull = 3.0 * kDeg;  // straight-pull: a pull this far off must fail

// ---------------------------------------------------------------- boxes

OrientedBox AxisBox(const Vec3& lo, const Vec3& hi, const std::string& tag) {
  if ((hi - lo).minCoeff() <= 0) throw std::logic_error("box-scene generator: empty box '" + tag + "'");
  OrientedBox b;
  b.center = (lo + hi) / 2;
  b.half_extents = (hi - lo) / 2;
  b.tag = tag;
  return b;
}

Vec3 ClosestPoint(const OrientedBox& box, const Vec3& p) {
  const Vec3 local = box.rotation.transpose() * (p - box.center);
  return box.center + box.rotation * local.cwiseMax(-box.half_extents).cwiseMin(box.half_extents);
}

double BoundingRadius(const OrientedBox& box) { return box.half_extents.norm(); }

// An axis-aligned rectangle of the design frame's xy-plane.
struct Rect {
  double x0, x1, y0, y1;
};

std::vector<double> SortedUnique(std::vector<double> v) {
  std::sort(v.begin(), v.end());
  v.erase(std::unique(v.begin(), v.end(), [](double a, double b) { return std::abs(a - b) < 1e-9; }), v.end());
  return v;
}

// The rectangle `outer` minus the union of `holes` (which may overlap), z in
// [z0, z1], as boxes: the bands between the holes' y edges cut into maximal
// solid x-runs, a run continued from the band below when it spans the same x:
// few boxes, none overlapping another.
std::vector<OrientedBox> SlabWithHoles(const Rect& outer, const std::vector<Rect>& holes, double z0, double z1,
                                       const std::string& tag) {
  std::vector<double> xs = {outer.x0, outer.x1}, ys = {outer.y0, outer.y1};
  for (const Rect& h : holes) {
    for (double x : {h.x0, h.x1}) xs.push_back(std::clamp(x, outer.x0, outer.x1));
    for (double y : {h.y0, h.y1}) ys.push_back(std::clamp(y, outer.y0, outer.y1));
  }
  xs = SortedUnique(xs);
  ys = SortedUnique(ys);
  auto solid = [&](double x, double y) {
    for (const Rect& h : holes) {
      if (x > h.x0 && x < h.x1 && y > h.y0 && y < h.y1) return false;
    }
    return true;
  };
  struct Run {
    double x0, x1, y0, y1;
  };
  std::vector<Run> done, open;
  for (size_t j = 0; j + 1 < ys.size(); ++j) {
    const double ym = 0.5 * (ys[j] + ys[j + 1]);
    std::vector<Run> band;
    for (size_t i = 0; i + 1 < xs.size(); ++i) {
      if (!solid(0.5 * (xs[i] + xs[i + 1]), ym)) continue;
      if (!band.empty() && band.back().x1 == xs[i]) {
        band.back().x1 = xs[i + 1];
      } else {
        band.push_back({xs[i], xs[i + 1], ys[j], ys[j + 1]});
      }
    }
    std::vector<Run> next;
    for (Run& r : band) {
      auto same = std::find_if(open.begin(), open.end(), [&](const Run& o) { return o.x0 == r.x0 && o.x1 == r.x1; });
      if (same != open.end()) {
        r.y0 = same->y0;
        open.erase(same);
      }
      next.push_back(r);
    }
    done.insert(done.end(), open.begin(), open.end());
    open = next;
  }
  done.insert(done.end(), open.begin(), open.end());
  std::vector<OrientedBox> out;
  for (const Run& r : done) out.push_back(AxisBox({r.x0, r.y0, z0}, {r.x1, r.y1, z1}, tag));
  return out;
}

// `box` turned by `angle` about the vertical axis through (c, 0).
OrientedBox TurnedAbout(const OrientedBox& box, const Vec2& c, double angle) {
  Pose turn;
  turn.q = Eigen::Quaterniond(Eigen::AngleAxisd(angle, Vec3::UnitZ()));
  const Vec3 at(c.x(), c.y(), 0);
  turn.t = at - turn.q * at;
  return Transformed(box, turn);
}

// A square tube around a square bore (centre c, bore half-width b, wall
// thickness w), z in [z0, z1], turned by `angle` about its axis: four
// boxes, the x-walls spanning the corners.
std::vector<OrientedBox> Tube(const Vec2& c, double b, double w, double z0, double z1, double angle,
                              const std::string& tag) {
  const double o = b + w;
  std::vector<OrientedBox> out = {AxisBox({c.x() - o, c.y() - o, z0}, {c.x() + o, c.y() - b, z1}, tag),
                                  AxisBox({c.x() - o, c.y() + b, z0}, {c.x() + o, c.y() + o, z1}, tag),
                                  AxisBox({c.x() - o, c.y() - b, z0}, {c.x() - b, c.y() + b, z1}, tag),
                                  AxisBox({c.x() + b, c.y() - b, z0}, {c.x() + o, c.y() + b, z1}, tag)};
  for (auto& box : out) box = TurnedAbout(box, c, angle);
  return out;
}

// ---------------------------------------------------------------- design

// A scene in its design frame: S's base plate top at z = 0, D above it,
// D's pull direction +z.
struct Design {
  std::vector<OrientedBox> s, rigid, clips;
  std::vector<int> clip_of_box;
  int clips_count = 0;
  std::vector<Pose> path;  // the known path without its last motion (the pull along +z)
  std::string path_summary;
  std::string description;
  std::vector<std::pair<std::string, double>> parameters;
};

// Builds a path motion by motion; each pose is D's pose (x -> q x + t).
class PathBuilder {
 public:
  PathBuilder() { path_.push_back(Pose{}); }

  // Rotates D by `angle` about the axis through `point` along `axis`, one
  // waypoint per kMaxStepAngle.
  void Rotate(const Vec3& point, const Vec3& axis, double angle) {
    const int steps = std::max(1, static_cast<int>(std::ceil(std::abs(angle) / kMaxStepAngle)));
    const Pose start = path_.back();
    for (int k = 1; k <= steps; ++k) {
      const Eigen::Quaterniond r(Eigen::AngleAxisd(angle * k / steps, axis.normalized()));
      Pose p;
      p.q = (r * start.q).normalized();
      p.t = r * (start.t - point) + point;
      path_.push_back(p);
    }
  }
  void Translate(const Vec3& delta) {
    Pose p = path_.back();
    p.t += delta;
    path_.push_back(p);
  }
  const std::vector<Pose>& path() const { return path_; }

 private:
  std::vector<Pose> path_;
};

// ---------------------------------------------------------------- clips

struct ClipShape {
  double thickness, width;                             // the beam: along the hook's direction, across it
  double hook_height, hook_penetration, hook_overlap;  // into the plate from below, beyond the hole's rim
  double wedge_half_thickness, wedge_angle, wedge_penetration, wedge_overlap;
  double front, back, side;  // the hole's room in front of (towards the rim), behind and beside the beam
};

ClipShape DrawClip(Random& r, bool thick, double plate) {
  ClipShape c;
  c.thickness = thick ? r.Uniform(2.5, 4.0) : r.Uniform(1.2, 2.0);
  c.width = thick ? r.Uniform(8.0, 12.0) : r.Uniform(5.0, 8.0);
  c.hook_height = thick ? r.Uniform(1.5, 2.5) : r.Uniform(1.2, 2.0);
  c.hook_penetration = r.Uniform(0.3, std::min(0.8, plate - 0.5));
  c.hook_overlap = r.Uniform(0.5, 1.5);
  c.wedge_half_thickness = thick ? r.Uniform(0.6, 1.0) : r.Uniform(0.4, 0.7);
  c.wedge_angle = r.Uniform(35.0, 50.0) * kDeg;
  c.wedge_penetration = r.Uniform(0.3, std::min(0.8, plate - 0.5));
  c.wedge_overlap = r.Uniform(0.5, 1.5);
  c.front = r.Uniform(0.4, 0.8);
  c.back = r.Uniform(1.5, 2.5);
  c.side = thick ? r.Uniform(1.0, 1.5) : r.Uniform(0.8, 1.2);
  return c;
}

// A snap clip at (x, y) hanging from the panel (down from `panel_mid`)
// through a hole of S's plate (z in [-plate, 0]). Its hook points along
// `out` (a unit vector along +-x or +-y): a hook box under the plate that
// reaches hook_overlap beyond the hole's rim and hook_penetration up into
// the plate, and below it a wedge (the insertion ramp, a box inclined by
// wedge_angle) from the beam's tip up to the rim, whose highest corner lies
// wedge_overlap beyond the rim and wedge_penetration up in the plate. Returns
// the hole.
Rect AddClip(Design* d, const Vec2& at, const Vec2& out, double panel_mid, double plate, const ClipShape& c) {
  const Vec3 es(out.x(), out.y(), 0), ew(-out.y(), out.x(), 0), ez = Vec3::UnitZ();
  const Vec3 base(at.x(), at.y(), 0);
  Mat3 frame;
  frame << es, ew, ez;
  auto box = [&](double s0, double s1, double z0, double z1, const std::string& tag) {
    OrientedBox b;
    b.center = base + es * (s0 + s1) / 2 + ez * (z0 + z1) / 2;
    b.rotation = frame;
    b.half_extents = Vec3((s1 - s0) / 2, c.width / 2, (z1 - z0) / 2);
    b.tag = tag;
    return b;
  };
  const double rim = c.thickness / 2 + c.front;
  const double hook_top = -plate + c.hook_penetration;
  const double a = c.wedge_angle, ht = c.wedge_half_thickness;
  const Vec2 u(std::cos(a), std::sin(a)), v(-std::sin(a), std::cos(a));  // (s, z): along the wedge, across it
  const Vec2 top(rim + c.wedge_overlap, -plate + c.wedge_penetration);   // the wedge's highest corner
  const Vec2 upper = top - ht * v;                                       // centre of its upper end
  const double length = upper.x() / u.x();                               // its lower end centred on the beam's axis
  const Vec2 lower = upper - length * u;
  const double tip = std::min(lower.y() - ht, hook_top - c.hook_height);

  const int id = d->clips_count++;
  d->clips.push_back(box(-c.thickness / 2, c.thickness / 2, tip, panel_mid, "clip-beam"));
  d->clips.push_back(box(-c.thickness / 2, rim + c.hook_overlap, hook_top - c.hook_height, hook_top, "clip-hook"));
  OrientedBox wedge;
  const Vec2 mid = (upper + lower) / 2;
  wedge.center = base + es * mid.x() + ez * mid.y();
  wedge.rotation << u.x() * es + u.y() * ez, ew, v.x() * es + v.y() * ez;
  wedge.half_extents = Vec3(length / 2, c.width / 2, ht);
  wedge.tag = "clip-wedge";
  d->clips.push_back(wedge);
  d->clip_of_box.insert(d->clip_of_box.end(), 3, id);

  const Vec3 p = base + es * (-c.thickness / 2 - c.back) + ew * (-c.width / 2 - c.side);
  const Vec3 q = base + es * rim + ew * (c.width / 2 + c.side);
  return {std::min(p.x(), q.x()), std::max(p.x(), q.x()), std::min(p.y(), q.y()), std::max(p.y(), q.y())};
}

// Walls along +-y beside the panel (S's flanges): part of the scenery near D.
void AddFlanges(Design* d, Random& r, const Rect& plate, double half_y, double top) {
  for (double side : {-1.0, 1.0}) {
    const double gap = r.Uniform(1.0, 2.5), t = r.Uniform(2.0, 3.0);
    const double y0 = side * (half_y + gap), y1 = side * (half_y + gap + t);
    d->s.push_back(AxisBox({plate.x0, std::min(y0, y1), 0}, {plate.x1, std::max(y0, y1), top}, "flange"));
  }
}

// A rib of D along x under the panel, its bottom `bottom` above S's plate;
// with `wall`, a wall of S stands beside it along its whole length (a y-gap
// of 0.5-2 mm), its top 0.8-2 mm under the panel. Motions in the xz-plane
// keep both gaps.
void AddRib(Design* d, Random& r, double x0, double x1, double y, double panel_under, double panel_mid, bool wall) {
  const double t = r.Uniform(1.2, 2.0), bottom = r.Uniform(0.5, 2.0);
  d->rigid.push_back(AxisBox({x0, y - t / 2, bottom}, {x1, y + t / 2, panel_mid}, "rib"));
  if (!wall) return;
  const double side = r.Uniform01() < 0.5 ? -1.0 : 1.0;
  const double gap = r.Uniform(0.5, 2.0), wt = r.Uniform(1.5, 2.5), top = panel_under - r.Uniform(0.8, 2.0);
  const double yw = y + side * (t / 2 + gap + wt / 2);
  d->s.push_back(AxisBox({x0 - 4, yw - wt / 2, 0}, {x1 + 4, yw + wt / 2, top}, "wall"));
}

// ---------------------------------------------------------------- families

// Trim panel, clips along +x, locating pin near them, L-rail on the -x edge
// whose foot reaches (-x) under the overhang of a bracket of S. The tilt axis
// runs along y through the overhang's free edge at the height of the foot's
// underside: the part of the foot under the overhang drops away from it while
// the rest of D rises, and the pin (12-16 mm inboard of the clips, 125-215 mm
// from the axis) moves sideways while in its hole by at most (the axis'
// height + the pin's engagement) x tilt <= (1.5 + 3.5) mm x 2 deg = 0.175 mm,
// under its smallest clearance, 0.25 mm.
Design TiltSlide(Random& r) {
  Design d;
  const double lx = r.Uniform(150, 230), ly = r.Uniform(100, 140);
  const double panel_t = r.Uniform(2.0, 3.5), plate = r.Uniform(1.5, 3.5);
  const int n_clips = 3 + static_cast<int>(r.Index(4));
  const ClipShape clip = DrawClip(r, false, plate);
  // The rail and the bracket's overhang (the lip).
  const double leg = r.Uniform(2.0, 3.0), foot = r.Uniform(1.5, 2.5), foot_lift = r.Uniform(0.8, 1.5);
  const double lip_gap = r.Uniform(0.2, 1.0), lip = r.Uniform(1.5, 2.5), leg_room = r.Uniform(1.0, 2.0);
  const double slide = r.Uniform(4.0, 7.0), engage = slide - r.Uniform(0.8, 1.3);
  const double tip_room = r.Uniform(0.8, 1.5), post = r.Uniform(2.0, 3.0);
  const double rail_len = r.Uniform(20, 40), rail_y = r.Uniform(-0.25, 0.25) * ly;
  const double lip_top = foot_lift + foot + lip_gap + lip;
  const double under = lip_top + r.Uniform(1.0, 2.0);  // the panel's underside, above the bracket
  const double panel_mid = under + panel_t / 2;
  const double tilt = r.Uniform(1.0, 2.0) * kDeg;

  const double leg0 = -lx / 2;            // the leg's outer face = the panel's -x edge
  const double axis_x = leg0 - leg_room;  // the overhang's free edge
  const double foot_tip = axis_x - engage;
  const double post1 = foot_tip - tip_room, post0 = post1 - post;
  const double ry0 = rail_y - rail_len / 2, ry1 = rail_y + rail_len / 2;

  d.rigid.push_back(AxisBox({-lx / 2, -ly / 2, under}, {lx / 2, ly / 2, under + panel_t}, "panel"));
  d.rigid.push_back(AxisBox({leg0, ry0, foot_lift}, {leg0 + leg, ry1, panel_mid}, "rail-leg"));
  d.rigid.push_back(AxisBox({foot_tip, ry0, foot_lift}, {leg0 + leg, ry1, foot_lift + foot}, "rail-foot"));
  d.s.push_back(AxisBox({post0, ry0 - 2, 0}, {post1, ry1 + 2, lip_top}, "bracket-post"));
  d.s.push_back(AxisBox({post0, ry0 - 2, lip_top - lip}, {axis_x, ry1 + 2, lip_top}, "bracket-lip"));

  // Clips in a row along the +x edge, hooks pointing outwards (+x).
  std::vector<Rect> holes;
  const double clip_x = lx / 2 - r.Uniform(7, 10);
  const double span = ly - 28, pitch = span / n_clips;
  const double jitter = std::clamp((pitch - clip.width - 2 * clip.side - 2) / 2, 0.0, 3.0);
  for (int k = 0; k < n_clips; ++k) {
    const double y = -span / 2 + (k + 0.5) * pitch + r.Uniform(-jitter, jitter);
    holes.push_back(AddClip(&d, {clip_x, y}, {1, 0}, panel_mid, plate, clip));
  }

  // The locating pin: in a hole of the plate, sometimes also in a sleeve on
  // it; `engagement` is how far it reaches below the bore's top, and the
  // tilt lifts its lowest corner 0.7 mm more than that.
  const double pin_x = clip_x - r.Uniform(12, 16), pin_y = r.Uniform(-0.5, 0.5) * (ly - 30);
  const double pin = r.Uniform(3.0, 5.0), pin_room = r.Uniform(0.25, 1.0);
  const double rise = (pin_x - pin / 2 - pin_room - axis_x) * std::sin(tilt);
  const double engagement = r.Uniform(1.0, std::max(1.0, std::min(3.5, rise - 0.7)));
  const double sleeve = (r.Uniform01() < 0.5 && engagement >= 2.2) ? r.Uniform(1.0, engagement - 1.0) : 0.0;
  const double bore = pin / 2 + pin_room;
  d.rigid.push_back(AxisBox({pin_x - pin / 2, pin_y - pin / 2, sleeve - engagement},
                            {pin_x + pin / 2, pin_y + pin / 2, panel_mid}, "pin"));
  holes.push_back({pin_x - bore, pin_x + bore, pin_y - bore, pin_y + bore});
  if (sleeve > 0) {
    for (const auto& b : Tube({pin_x, pin_y}, bore, r.Uniform(1.2, 2.0), 0, sleeve, 0, "sleeve")) d.s.push_back(b);
  }

  // Ribs in lanes across y, between the rail and the pin; most have a wall
  // of S beside them.
  const int n_ribs = 2 + static_cast<int>(r.Index(3));
  const double rib_x0 = leg0 + 15, rib_x1 = pin_x - 12, lane = (ly - 20) / n_ribs;
  for (int k = 0; k < n_ribs; ++k) {
    const double y = -ly / 2 + 10 + (k + 0.5) * lane + r.Uniform(-2, 2);
    const double len = r.Uniform(25, std::min(60.0, rib_x1 - rib_x0));
    const double x0 = r.Uniform(rib_x0, rib_x1 - len);
    AddRib(&d, r, x0, x0 + len, y, under, panel_mid, k == 0 || r.Uniform01() < 0.6);
  }

  const Rect plate_rect{post0 - r.Uniform(5, 8), lx / 2 + r.Uniform(8, 12), 0, 0};
  const double flange_top = under + panel_t + r.Uniform(1.0, 3.0);
  AddFlanges(&d, r, plate_rect, ly / 2, flange_top);
  const double plate_y = ly / 2 + 2.5 + 3.0 + r.Uniform(3, 6);
  const Rect outer{plate_rect.x0, plate_rect.x1, -plate_y, plate_y};
  for (auto& b : SlabWithHoles(outer, holes, -plate, 0, "plate")) d.s.push_back(b);

  PathBuilder path;
  path.Rotate({axis_x, 0, foot_lift}, Vec3::UnitY(), -tilt);  // -tilt about +y lifts +x
  path.Translate({slide, 0, 0});
  d.path = path.path();
  char text[512];
  std::snprintf(text, sizeof text, "tilt %.2f deg about the rail (clip side up), slide %.2f mm", tilt / kDeg, slide);
  d.path_summary = text;
  std::snprintf(text, sizeof text,
                "Trim panel (%.0fx%.0f mm) on a base plate: %d snap clips on the +x edge whose hooks and wedges "
                "overlap the rims of their holes, a locating pin near them (%.2f mm clearance) and a rigid L-shaped "
                "guide rail on the -x edge whose foot sits %.2f mm under a lip of S.",
                lx, ly, n_clips, pin_room, lip_gap);
  d.description = std::string(text) +
                  " Disassembly: tilt 1-2 degrees about the rail (clip side up, pin out), slide 4-7 mm in +x to free "
                  "the foot, lift.";
  d.parameters = {{"panel_x_mm", lx},
                  {"panel_y_mm", ly},
                  {"panel_thickness_mm", panel_t},
                  {"plate_thickness_mm", plate},
                  {"clips", n_clips},
                  {"clip_hook_overlap_mm", clip.hook_overlap},
                  {"clip_wedge_overlap_mm", clip.wedge_overlap},
                  {"rail_lip_gap_mm", lip_gap},
                  {"rail_foot_engagement_mm", engage},
                  {"pin_clearance_mm", pin_room},
                  {"pin_engagement_mm", engagement},
                  {"pin_sleeve_height_mm", sleeve},
                  {"ribs", n_ribs},
                  {"tilt_deg", tilt / kDeg},
                  {"slide_mm", slide}};
  return d;
}

// Panel with thick clips on its edges and 2-4 square guide pins in sleeves
// (square tubes through the plate, as bushings). A pull tilted by kWrongPull
// drifts sideways by engagement x tan(kWrongPull) before the pins are out.
// A square pin stops a drift only by its component across a wall, down to
// 1/sqrt(2) of it diagonally; every second pin and sleeve is turned by 45
// degrees, so that some pin sees at least cos(22.5 deg) of the drift in any
// direction, and the clearance is drawn 0.1 mm under that (the oracle's
// tolerance is 0.05 mm).
Design StraightPull(Random& r) {
  Design d;
  const double lx = r.Uniform(140, 200), ly = r.Uniform(100, 140);
  const double panel_t = r.Uniform(2.5, 3.5), plate = r.Uniform(1.5, 3.5);
  const int n_clips = 3 + static_cast<int>(r.Index(3)), n_pins = 2 + static_cast<int>(r.Index(3));
  const ClipShape clip = DrawClip(r, true, plate);
  const double pin_len = r.Uniform(8, 12), top_gap = r.Uniform(0.3, 0.6), tip_depth = r.Uniform(0.3, plate - 0.3);
  const double under = pin_len - tip_depth, panel_mid = under + panel_t / 2;
  const double engagement = pin_len - top_gap;
  const double room_max = std::min(0.35, std::cos(22.5 * kDeg) * engagement * std::tan(kWrongPull) - 0.1);

  d.rigid.push_back(AxisBox({-lx / 2, -ly / 2, under}, {lx / 2, ly / 2, under + panel_t}, "panel"));
  std::vector<Rect> holes;
  // Pins near the quadrants' centres.
  std::vector<Vec2> spots = {{-lx / 4, -ly / 4}, {lx / 4, -ly / 4}, {-lx / 4, ly / 4}, {lx / 4, ly / 4}};
  for (size_t k = spots.size() - 1; k > 0; --k) std::swap(spots[k], spots[r.Index(k + 1)]);
  double min_room = 1e9;
  for (int k = 0; k < n_pins; ++k) {
    const Vec2 c = spots[k] + Vec2(r.Uniform(-3, 3), r.Uniform(-3, 3));
    const double pin = r.Uniform(4.0, 6.0), room = r.Uniform(0.2, room_max), bore = pin / 2 + room;
    const double wall = r.Uniform(1.2, 2.0), angle = (k % 2) * 45.0 * kDeg;
    min_room = std::min(min_room, room);
    d.rigid.push_back(TurnedAbout(AxisBox({c.x() - pin / 2, c.y() - pin / 2, -tip_depth},
                                          {c.x() + pin / 2, c.y() + pin / 2, panel_mid}, "guide-pin"),
                                  c, angle));
    for (const auto& b : Tube(c, bore, wall, -plate, under - top_gap, angle, "sleeve")) d.s.push_back(b);
    // The plate's hole takes the whole (turned) tube.
    const double hole = (bore + wall) * (std::abs(std::cos(angle)) + std::abs(std::sin(angle)));
    holes.push_back({c.x() - hole, c.x() + hole, c.y() - hole, c.y() + hole});
  }
  // Clips in 8 slots, two per edge, hooks pointing outwards.
  struct Slot {
    Vec2 at, out;
  };
  std::vector<Slot> slots;
  for (double f : {-1.0, 1.0}) {
    slots.push_back({{lx / 2, f * ly / 6}, {1, 0}});
    slots.push_back({{-lx / 2, f * ly / 6}, {-1, 0}});
    slots.push_back({{f * lx / 6, ly / 2}, {0, 1}});
    slots.push_back({{f * lx / 6, -ly / 2}, {0, -1}});
  }
  for (size_t k = slots.size() - 1; k > 0; --k) std::swap(slots[k], slots[r.Index(k + 1)]);
  for (int k = 0; k < n_clips; ++k) {
    const Slot& s = slots[k];
    const Vec2 along(-s.out.y(), s.out.x());
    const Vec2 at = s.at - s.out * r.Uniform(8, 11) + along * r.Uniform(-3, 3);
    holes.push_back(AddClip(&d, at, s.out, panel_mid, plate, clip));
  }
  // Ribs in the strip between the pins, along x.
  const int n_ribs = 1 + static_cast<int>(r.Index(2));
  for (int k = 0; k < n_ribs; ++k) {
    const double y = n_ribs == 1 ? r.Uniform(-3, 3) : (k == 0 ? -1 : 1) * r.Uniform(3.5, 5.0);
    const double len = r.Uniform(20, lx / 2 - 24), x0 = r.Uniform(-lx / 4 + 12, lx / 4 - 12 - len);
    AddRib(&d, r, x0, x0 + len, y, under, panel_mid, true);
  }
  const double margin = r.Uniform(8, 12);
  const Rect plate_rect{-lx / 2 - margin, lx / 2 + margin, 0, 0};
  AddFlanges(&d, r, plate_rect, ly / 2, under + panel_t + r.Uniform(1.0, 3.0));
  const double plate_y = ly / 2 + 2.5 + 3.0 + r.Uniform(3, 6);
  for (auto& b : SlabWithHoles({plate_rect.x0, plate_rect.x1, -plate_y, plate_y}, holes, -plate, 0, "plate")) {
    d.s.push_back(b);
  }

  PathBuilder path;
  path.Translate({0, 0, pin_len + 1.0});  // the pins are out of their sleeves
  d.path = path.path();
  d.path_summary = "";  // the pull is all there is
  char text[512];
  std::snprintf(text, sizeof text,
                "Bracket panel (%.0fx%.0f mm) held by %d thick snap clips and guided by %d rigid pins (%.1f mm long) "
                "in sleeves with %.2f-%.2f mm clearance per side.",
                lx, ly, n_clips, n_pins, pin_len, min_room, room_max);
  d.description = std::string(text) +
                  " Only a straight pull along the panel normal works; 3 degrees off or 0.5 mm sideways first fails.";
  d.parameters = {{"panel_x_mm", lx},
                  {"panel_y_mm", ly},
                  {"panel_thickness_mm", panel_t},
                  {"plate_thickness_mm", plate},
                  {"clips", n_clips},
                  {"clip_thickness_mm", clip.thickness},
                  {"clip_hook_overlap_mm", clip.hook_overlap},
                  {"clip_wedge_overlap_mm", clip.wedge_overlap},
                  {"guide_pins", n_pins},
                  {"pin_length_mm", pin_len},
                  {"pin_engagement_mm", engagement},
                  {"pin_min_clearance_mm", min_room},
                  {"sleeve_top_gap_mm", top_gap},
                  {"ribs", n_ribs}};
  return d;
}

// A T-shaped part in an L-shaped T-slot of S: its tongue (head) under the
// roof of a channel, its neck in a slot of the roof, a cap (a block or a
// small panel) above the roof. The tongue starts at the closed end of leg A
// (along x); leg B (along +-y) ends under an opening of the roof.
Design Channel(Random& r) {
  Design d;
  const double plate = r.Uniform(2.0, 3.5);
  const double head = r.Uniform(10, 18), head_h = r.Uniform(3, 6);
  const double floor_gap = r.Uniform(0.2, 1.0), roof_gap = r.Uniform(0.2, 1.0), side = r.Uniform(0.2, 1.0);
  const double roof = r.Uniform(1.5, 3.0);
  const double neck = r.Uniform(4, std::min(7.0, head - 5)), neck_room = r.Uniform(0.2, 1.0);
  const double cap_gap = r.Uniform(0.3, 1.0);
  const double leg_a = r.Uniform(20, 45), leg_b = r.Uniform(20, 45), sign = r.Uniform01() < 0.5 ? -1.0 : 1.0;
  const double wall = r.Uniform(3, 6);
  const bool block = r.Uniform01() < 0.5;
  const double cap_x = block ? head + r.Uniform(4, 12) : r.Uniform(40, 70);
  const double cap_y = block ? cap_x : r.Uniform(30, 50);
  const double cap_t = block ? r.Uniform(4, 8) : r.Uniform(2.0, 3.0);

  const double w = head + 2 * side, sw = neck + 2 * neck_room;
  const double height = floor_gap + head_h + roof_gap;  // the channel's
  auto ys = [&](double lo, double hi) { return sign > 0 ? std::make_pair(lo, hi) : std::make_pair(-hi, -lo); };
  auto rect_y = [&](double x0, double x1, double lo, double hi) {
    const auto [y0, y1] = ys(lo, hi);
    return Rect{x0, x1, y0, y1};
  };
  const Rect leg_a_rect{-leg_a - w / 2, w / 2, -w / 2, w / 2};
  const Rect leg_b_rect = rect_y(-w / 2, w / 2, -w / 2, leg_b + w / 2);
  const Rect slot_a{-leg_a - sw / 2, sw / 2, -sw / 2, sw / 2};
  const Rect slot_b = rect_y(-sw / 2, sw / 2, -sw / 2, leg_b);
  const Rect exit = rect_y(-w / 2, w / 2, leg_b - w / 2, leg_b + w / 2);
  const auto [by0, by1] = ys(-w / 2 - wall, leg_b + w / 2 + wall);
  const Rect body{-leg_a - w / 2 - wall, w / 2 + wall, by0, by1};
  const double margin = r.Uniform(8, 15);

  for (auto& b : SlabWithHoles({body.x0 - margin, body.x1 + margin, body.y0 - margin, body.y1 + margin}, {}, -plate, 0,
                               "plate")) {
    d.s.push_back(b);
  }
  for (auto& b : SlabWithHoles(body, {leg_a_rect, leg_b_rect}, 0, height, "channel-wall")) d.s.push_back(b);
  for (auto& b : SlabWithHoles(body, {slot_a, slot_b, exit}, height, height + roof, "roof")) d.s.push_back(b);

  const double x = -leg_a, cap_z = height + roof + cap_gap;
  d.rigid.push_back(
      AxisBox({x - head / 2, -head / 2, floor_gap}, {x + head / 2, head / 2, floor_gap + head_h}, "tongue"));
  d.rigid.push_back(
      AxisBox({x - neck / 2, -neck / 2, floor_gap + head_h / 2}, {x + neck / 2, neck / 2, cap_z + cap_t / 2}, "neck"));
  d.rigid.push_back(
      AxisBox({x - cap_x / 2, -cap_y / 2, cap_z}, {x + cap_x / 2, cap_y / 2, cap_z + cap_t}, block ? "cap" : "panel"));

  PathBuilder path;
  path.Translate({leg_a, 0, 0});
  path.Translate({0, sign * leg_b, 0});
  d.path = path.path();
  char text[512];
  std::snprintf(text, sizeof text, "slide %.1f mm along x, then %.1f mm along %sy", leg_a, leg_b, sign > 0 ? "+" : "-");
  d.path_summary = text;
  std::snprintf(text, sizeof text,
                "A %s with a %.0f mm tongue under the roof of an L-shaped T-slot of S (clearances %.2f mm beside, "
                "%.2f below, %.2f above), its neck in the roof's slot (%.2f mm).",
                block ? "block" : "small panel", head, side, floor_gap, roof_gap, neck_room);
  d.description = std::string(text) +
                  " No clips, no initial intersection. Disassembly: slide along the first leg of the L to its corner, "
                  "along the second leg to the roof's opening, lift out.";
  d.parameters = {{"tongue_mm", head},
                  {"tongue_height_mm", head_h},
                  {"side_clearance_mm", side},
                  {"floor_clearance_mm", floor_gap},
                  {"roof_clearance_mm", roof_gap},
                  {"neck_mm", neck},
                  {"neck_clearance_mm", neck_room},
                  {"cap_clearance_mm", cap_gap},
                  {"cap_is_block", block ? 1.0 : 0.0},
                  {"leg_a_mm", leg_a},
                  {"leg_b_mm", leg_b},
                  {"leg_b_sign", sign},
                  {"plate_thickness_mm", plate}};
  return d;
}

// ---------------------------------------------------------------- output

std::string Num(double v, const char* format = "%.17g") {
  char buf[64];
  std::snprintf(buf, sizeof buf, format, v == 0 ? 0.0 : v);  // no "-0"
  return buf;
}

std::string JsonVec(const Vec3& v, const char* format = "%.17g") {
  return "[" + Num(v.x(), format) + ", " + Num(v.y(), format) + ", " + Num(v.z(), format) + "]";
}

std::string JsonString(const std::string& s) {
  std::string out = "\"";
  for (char c : s) {
    if (c == '"' || c == '\\') out += '\\';
    out += c;
  }
  return out + "\"";
}

std::string BoxesJson(const BoxScene& scene) {
  std::string j = "{\n";
  j += " \"format\": \"obb-v1\",\n";
  j += " \"convention\": \"world frame, installed pose; point = center + rotation @ u, u in [-half_extents, "
       "+half_extents]; rotation is row-major, its columns are the box axes\",\n";
  j += " \"units\": \"mm\",\n";
  auto list = [&](const char* name, const std::vector<OrientedBox>& boxes) {
    j += std::string(" \"") + name + "\": [";
    for (size_t k = 0; k < boxes.size(); ++k) {
      const OrientedBox& b = boxes[k];
      const Mat3& R = b.rotation;
      j += k == 0 ? "\n" : ",\n";
      j += "  {\"id\": " + std::to_string(k) + ", \"tag\": " + JsonString(b.tag) +
           ", \"center\": " + JsonVec(b.center) + ", \"rotation\": [" + JsonVec(R.row(0).transpose()) + ", " +
           JsonVec(R.row(1).transpose()) + ", " + JsonVec(R.row(2).transpose()) +
           "], \"half_extents\": " + JsonVec(b.half_extents) + "}";
    }
    j += boxes.empty() ? "],\n" : "\n ],\n";
  };
  list("static", scene.static_boxes);
  list("dynamic_rigid", scene.rigid_boxes);
  list("dynamic_clips", scene.clip_boxes);
  j += " \"dynamic_stl_box_order\": [";
  for (size_t k = 0; k < scene.dynamic_box_order.size(); ++k) {
    j += (k == 0 ? "" : ", ") + std::to_string(scene.dynamic_box_order[k]);
  }
  j += "]\n}\n";
  return j;
}

void PutU32(std::string* out, std::uint32_t v) {
  for (int k = 0; k < 4; ++k) out->push_back(static_cast<char>((v >> (8 * k)) & 0xff));
}

void PutF32(std::string* out, double v) {
  const float f = static_cast<float>(v);
  std::uint32_t bits;
  std::memcpy(&bits, &f, sizeof bits);
  PutU32(out, bits);
}

// Binary STL (little-endian), the boxes' shells one after another. The
// header must not start with "solid" (readers would take it for ASCII).
std::string BinaryStl(const std::vector<const OrientedBox*>& boxes, BoxTessellation tessellation,
                      const std::string& what) {
  std::vector<TriangleMesh> shells;
  std::uint32_t count = 0;
  for (const OrientedBox* b : boxes) {
    shells.push_back(BoxShell(*b, tessellation));
    count += static_cast<std::uint32_t>(shells.back().triangles.size());
  }
  std::string header = "binary STL " + what + ", mm, closed boxes (not merged), ausbau-scene-gen";
  header.resize(80, ' ');
  std::string out = header;
  out.reserve(84 + 50 * static_cast<size_t>(count));
  PutU32(&out, count);
  for (const TriangleMesh& m : shells) {
    for (const auto& t : m.triangles) {
      const Vec3 &a = m.vertices[t[0]], &b = m.vertices[t[1]], &c = m.vertices[t[2]];
      const Vec3 n = (b - a).cross(c - a).normalized();
      for (const Vec3& p : {n, a, b, c}) {
        for (int k = 0; k < 3; ++k) PutF32(&out, p[k]);
      }
      out.append(2, '\0');
    }
  }
  return out;
}

// D's world AABB at a pose, from the boxes' corners (as the oracle takes it).
Aabb DynamicBounds(const BoxScene& scene, const Pose& pose) {
  Aabb box;
  for (const auto* list : {&scene.rigid_boxes, &scene.clip_boxes}) {
    for (const OrientedBox& b : *list) {
      for (const Vec3& c : Corners(b)) box.Extend(pose.Apply(c));
    }
  }
  return box;
}

Aabb StaticBounds(const BoxScene& scene) {
  Aabb box;
  for (const OrientedBox& b : scene.static_boxes) {
    for (const Vec3& c : Corners(b)) box.Extend(c);
  }
  return box;
}

}  // namespace

// ---------------------------------------------------------------- public

std::vector<std::string> BoxSceneFamilies() { return {"panel-tilt-slide", "panel-straight-pull", "panel-channel"}; }

bool IsBoxSceneFamily(const std::string& family) {
  const auto f = BoxSceneFamilies();
  return std::find(f.begin(), f.end(), family) != f.end();
}

BoxTessellation ParseBoxTessellation(const std::string& text) {
  if (text == "coarse") return BoxTessellation::kCoarse;
  if (text == "fine") return BoxTessellation::kFine;
  throw InputError("--tessellation: expected coarse or fine (got '" + text + "')");
}

BoxWorld ParseBoxWorld(const std::string& text) {
  if (text == "identity") return BoxWorld::kIdentity;
  if (text == "random") return BoxWorld::kRandom;
  throw InputError("--world: expected identity or random (got '" + text + "')");
}

OrientedBox Transformed(const OrientedBox& box, const Pose& pose) {
  OrientedBox out = box;
  const Mat3 R = pose.q.toRotationMatrix();
  out.center = R * box.center + pose.t;
  out.rotation = R * box.rotation;
  return out;
}

std::array<Vec3, 8> Corners(const OrientedBox& box) {
  std::array<Vec3, 8> out;
  for (int i = 0; i < 8; ++i) {
    const Vec3 u((i & 1) ? 1 : -1, (i & 2) ? 1 : -1, (i & 4) ? 1 : -1);
    out[i] = box.center + box.rotation * u.cwiseProduct(box.half_extents);
  }
  return out;
}

double BoxPenetration(const OrientedBox& a, const OrientedBox& b) {
  const Vec3 d = b.center - a.center;
  double depth = std::numeric_limits<double>::infinity();
  auto test = [&](const Vec3& axis) {  // unit axis
    double ra = 0, rb = 0;
    for (int k = 0; k < 3; ++k) {
      ra += a.half_extents[k] * std::abs(axis.dot(a.rotation.col(k)));
      rb += b.half_extents[k] * std::abs(axis.dot(b.rotation.col(k)));
    }
    depth = std::min(depth, ra + rb - std::abs(axis.dot(d)));
  };
  for (int k = 0; k < 3; ++k) {
    test(a.rotation.col(k));
    test(b.rotation.col(k));
  }
  for (int i = 0; i < 3; ++i) {
    for (int k = 0; k < 3; ++k) {
      const Vec3 axis = a.rotation.col(i).cross(b.rotation.col(k));
      const double n = axis.norm();
      if (n > 1e-6) test(axis / n);  // parallel edges: their axis is one of the face axes' span
    }
  }
  return depth;
}

double BoxDistance(const OrientedBox& a, const OrientedBox& b) {
  if (BoxPenetration(a, b) >= 0) return 0;
  // Alternating projections converge to a closest pair of two disjoint
  // convex sets; the projection onto a box is a clamp in its frame.
  Vec3 pb = b.center, pa = ClosestPoint(a, pb);
  for (int k = 0; k < 100000; ++k) {
    const Vec3 nb = ClosestPoint(b, pa);
    const Vec3 na = ClosestPoint(a, nb);
    const bool still = (nb - pb).norm() < 1e-13 && (na - pa).norm() < 1e-13;
    pa = na;
    pb = nb;
    if (still) break;
  }
  return (pa - pb).norm();
}

TriangleMesh BoxShell(const OrientedBox& box, BoxTessellation tessellation) {
  int n[3];
  for (int a = 0; a < 3; ++a) {
    n[a] = tessellation == BoxTessellation::kCoarse
               ? 1
               : std::max(4, static_cast<int>(std::ceil(2 * box.half_extents[a] / kFineEdge - 1e-9)));
  }
  // The lattice points on the surface, numbered once, so that faces share
  // their border vertices (a closed shell with no T-junctions).
  TriangleMesh m;
  std::vector<int> id(static_cast<size_t>(n[0] + 1) * (n[1] + 1) * (n[2] + 1), -1);
  auto vertex = [&](const int(&i)[3]) {
    int& v = id[(static_cast<size_t>(i[2]) * (n[1] + 1) + i[1]) * (n[0] + 1) + i[0]];
    if (v < 0) {
      Vec3 u;
      for (int a = 0; a < 3; ++a) {
        u[a] = i[a] == n[a] ? box.half_extents[a] : box.half_extents[a] * (2.0 * i[a] / n[a] - 1.0);
      }
      v = static_cast<int>(m.vertices.size());
      m.vertices.push_back(box.center + box.rotation * u);
    }
    return v;
  };
  for (int a = 0; a < 3; ++a) {
    const int b = (a + 1) % 3, c = (a + 2) % 3;  // e_b x e_c = e_a
    for (int side = 0; side < 2; ++side) {
      for (int j = 0; j < n[b]; ++j) {
        for (int k = 0; k < n[c]; ++k) {
          int p00[3], p10[3], p11[3], p01[3];
          p00[a] = p10[a] = p11[a] = p01[a] = side * n[a];
          p00[b] = j, p00[c] = k;
          p10[b] = j + 1, p10[c] = k;
          p11[b] = j + 1, p11[c] = k + 1;
          p01[b] = j, p01[c] = k + 1;
          const int v00 = vertex(p00), v10 = vertex(p10), v11 = vertex(p11), v01 = vertex(p01);
          if (side == 1) {  // +a face: counter-clockwise seen from outside
            m.triangles.push_back({v00, v10, v11});
            m.triangles.push_back({v00, v11, v01});
          } else {
            m.triangles.push_back({v00, v11, v10});
            m.triangles.push_back({v00, v01, v11});
          }
        }
      }
    }
  }
  return m;
}

BoxScene BuildBoxScene(const std::string& family, const BoxSceneOptions& options) {
  Random geometry(options.seed);
  Design d;
  if (family == "panel-tilt-slide") {
    d = TiltSlide(geometry);
  } else if (family == "panel-straight-pull") {
    d = StraightPull(geometry);
  } else if (family == "panel-channel") {
    d = Channel(geometry);
  } else {
    throw InputError("--family: unknown family '" + family +
                     "' (expected panel-tilt-slide, panel-straight-pull or panel-channel)");
  }

  BoxScene scene;
  scene.family = family;
  scene.options = options;
  scene.description = d.description;
  scene.parameters = d.parameters;
  scene.min_clearance = kMinClearance;
  scene.clips = d.clips_count;
  scene.clip_of_box = d.clip_of_box;

  // A stream of its own, drawn in full for both placements, so that the
  // identity and the random scene of a seed differ only by the placement.
  Random placement(options.seed ^ 0x9e3779b97f4a7c15ULL);
  const Eigen::Quaterniond rotation = placement.UniformQuaternion();
  Vec3 direction(placement.Normal(), placement.Normal(), placement.Normal());
  if (direction.norm() < 1e-9) direction = Vec3::UnitX();
  const double distance = placement.Uniform(2000, 4000);
  const int n_dynamic = static_cast<int>(d.rigid.size() + d.clips.size());
  scene.dynamic_box_order.resize(n_dynamic);
  std::iota(scene.dynamic_box_order.begin(), scene.dynamic_box_order.end(), 0);
  for (int k = n_dynamic - 1; k > 0; --k)
    std::swap(scene.dynamic_box_order[k], scene.dynamic_box_order[placement.Index(k + 1)]);
  if (options.world == BoxWorld::kRandom) {
    scene.world.q = rotation.normalized();
    scene.world.t = distance * direction.normalized();
  }

  for (const auto& b : d.s) scene.static_boxes.push_back(Transformed(b, scene.world));
  for (const auto& b : d.rigid) scene.rigid_boxes.push_back(Transformed(b, scene.world));
  for (const auto& b : d.clips) scene.clip_boxes.push_back(Transformed(b, scene.world));

  // The path in world terms: W P W^-1 for each design pose P.
  const Mat3 Rw = scene.world.q.toRotationMatrix();
  scene.path.push_back(Pose{});
  for (size_t k = 1; k < d.path.size(); ++k) {
    Pose p;
    p.q = (scene.world.q * d.path[k].q * scene.world.q.conjugate()).normalized();
    p.t = Rw * d.path[k].t + scene.world.t - p.q * scene.world.t;
    scene.path.push_back(p);
  }
  // Last, the pull along S's normal until the world AABBs are kFinalGap apart
  // (the oracle's end condition): the shortest pull over the three axes.
  scene.pull_direction = Rw * Vec3::UnitZ();
  const Aabb s_box = StaticBounds(scene), d_box = DynamicBounds(scene, scene.path.back());
  double pull = std::numeric_limits<double>::infinity();
  for (int a = 0; a < 3; ++a) {
    const double n = scene.pull_direction[a];
    if (n > 1e-9) pull = std::min(pull, (s_box.max[a] + kFinalGap - d_box.min[a]) / n);
    if (n < -1e-9) pull = std::min(pull, (d_box.max[a] - s_box.min[a] + kFinalGap) / -n);
  }
  Pose last = scene.path.back();
  last.t += std::max(pull, kFinalGap) * scene.pull_direction;
  scene.path.push_back(last);
  char text[96];
  if (d.path_summary.empty()) {
    std::snprintf(text, sizeof text, "straight pull of %.1f mm along the panel normal", std::max(pull, kFinalGap));
    scene.path_summary = text;
  } else {
    std::snprintf(text, sizeof text, ", lift %.1f mm", std::max(pull, kFinalGap));
    scene.path_summary = d.path_summary + text;
  }

  // The ground truth must hold: no rigid box of D may touch S on the path.
  const double depth = MaxRigidPenetration(scene, scene.path, 0.1);
  if (depth > 0) {
    throw std::logic_error("box-scene generator: " + family + " seed " + std::to_string(options.seed) +
                           ": the known path penetrates S by " + Num(depth, "%.4f") + " mm");
  }
  return scene;
}

BoxSceneContacts InstalledContacts(const BoxScene& scene) {
  BoxSceneContacts c;
  c.rigid_min_clearance = c.rigid_min_separation = std::numeric_limits<double>::infinity();
  for (const OrientedBox& d : scene.rigid_boxes) {
    for (const OrientedBox& s : scene.static_boxes) {
      const double separation = -BoxPenetration(d, s);
      c.rigid_min_separation = std::min(c.rigid_min_separation, separation);
      if (separation < c.rigid_min_clearance)
        c.rigid_min_clearance = std::min(c.rigid_min_clearance, BoxDistance(d, s));
    }
  }
  c.clip_intersects.assign(scene.clips, false);
  for (size_t k = 0; k < scene.clip_boxes.size(); ++k) {
    for (const OrientedBox& s : scene.static_boxes) {
      const double depth = BoxPenetration(scene.clip_boxes[k], s);
      if (depth <= 0) continue;
      ++c.clip_static_overlapping_pairs;
      c.max_clip_penetration = std::max(c.max_clip_penetration, depth);
      c.clip_intersects[scene.clip_of_box[k]] = true;
    }
  }
  return c;
}

double MaxRigidPenetration(const BoxScene& scene, const std::vector<Pose>& path, double step) {
  constexpr double kReach = 1.0;  // pairs whose bounding spheres are farther apart are not tested
  double radius = 0;
  for (const auto* list : {&scene.rigid_boxes, &scene.clip_boxes}) {
    for (const OrientedBox& b : *list) {
      for (const Vec3& c : Corners(b)) radius = std::max(radius, c.norm());
    }
  }
  double worst = -kReach;
  auto check = [&](const Pose& pose) {
    for (const OrientedBox& d : scene.rigid_boxes) {
      const OrientedBox moved = Transformed(d, pose);
      const double rd = BoundingRadius(moved);
      for (const OrientedBox& s : scene.static_boxes) {
        if ((moved.center - s.center).norm() > rd + BoundingRadius(s) + kReach) continue;
        worst = std::max(worst, BoxPenetration(moved, s));
      }
    }
  };
  if (path.empty()) return worst;
  for (size_t k = 0; k + 1 < path.size(); ++k) {
    const int n = std::max(1, static_cast<int>(std::ceil(MaxDisplacement(path[k], path[k + 1], radius) / step)));
    for (int i = 0; i < n; ++i) check(Interpolate(path[k], path[k + 1], static_cast<double>(i) / n));
  }
  check(path.back());
  return worst;
}

BoxSceneFiles WriteBoxScene(const BoxScene& scene, const fs::path& dir) {
  fs::create_directories(dir / "truth");
  BoxSceneFiles files;
  files.scene_yaml = dir / "scene.yaml";
  files.boxes_json = dir / "boxes.json";
  files.scene_json = dir / "scene.json";
  files.labels = dir / "truth" / "labels_per_triangle.txt";
  files.known_path = dir / "truth" / "known_path.csv";
  const std::string name = scene.family + "-s" + std::to_string(scene.options.seed);
  const BoxTessellation tess = scene.options.tessellation;

  std::vector<const OrientedBox*> s_boxes, d_boxes, rigid, clips;
  for (const auto& b : scene.static_boxes) s_boxes.push_back(&b);
  for (const auto& b : scene.rigid_boxes) rigid.push_back(&b);
  for (const auto& b : scene.clip_boxes) clips.push_back(&b);
  std::string labels;
  std::int64_t d_triangles = 0;
  const int n_rigid = static_cast<int>(scene.rigid_boxes.size());
  for (int k : scene.dynamic_box_order) {
    const bool clip = k >= n_rigid;
    d_boxes.push_back(clip ? clips[k - n_rigid] : rigid[k]);
    const size_t n = BoxShell(*d_boxes.back(), tess).triangles.size();
    for (size_t t = 0; t < n; ++t) labels += clip ? "1\n" : "0\n";
    d_triangles += static_cast<std::int64_t>(n);
  }
  std::int64_t s_triangles = 0;
  for (const OrientedBox* b : s_boxes) s_triangles += static_cast<std::int64_t>(BoxShell(*b, tess).triangles.size());

  WriteTextFileAtomically(dir / "static.stl", BinaryStl(s_boxes, tess, "static"));
  WriteTextFileAtomically(dir / "dynamic.stl", BinaryStl(d_boxes, tess, "dynamic"));
  WriteTextFileAtomically(dir / "truth" / "dynamic_rigid.stl", BinaryStl(rigid, tess, "dynamic_rigid"));
  if (!clips.empty()) {
    WriteTextFileAtomically(dir / "truth" / "dynamic_clips.stl", BinaryStl(clips, tess, "dynamic_clips"));
  }
  WriteTextFileAtomically(files.labels, labels);
  WriteTextFileAtomically(files.boxes_json, BoxesJson(scene));
  WriteTextFileAtomically(files.scene_yaml, "format: ausbau-scene/1\nname: " + name +
                                                "\nunits: mm\nstatic: [static.stl]\ndynamic: dynamic.stl\n");

  std::string csv = "x,y,z,qw,qx,qy,qz\n";
  for (const Pose& p : scene.path) {
    Eigen::Quaterniond q = p.q;
    if (q.w() < 0) q.coeffs() *= -1;
    csv += Num(p.t.x()) + "," + Num(p.t.y()) + "," + Num(p.t.z()) + "," + Num(q.w()) + "," + Num(q.x()) + "," +
           Num(q.y()) + "," + Num(q.z()) + "\n";
  }
  WriteTextFileAtomically(files.known_path, csv);

  // scene.json: what a reader needs without running anything.
  const BoxSceneContacts contacts = InstalledContacts(scene);
  const double path_separation = -MaxRigidPenetration(scene, scene.path, 0.1);
  double length = 0, angle = 0;
  for (size_t k = 0; k + 1 < scene.path.size(); ++k) {
    length += (scene.path[k + 1].t - scene.path[k].t).norm();
    angle += RotationAngle(scene.path[k].q, scene.path[k + 1].q);
  }
  const bool all_clips_intersect =
      scene.clips > 0 &&
      std::all_of(contacts.clip_intersects.begin(), contacts.clip_intersects.end(), [](bool b) { return b; });
  const char* g = "%.6g";
  std::string j = "{\n";
  j += " \"family\": " + JsonString(scene.family) + ",\n";
  j += " \"seed\": " + std::to_string(scene.options.seed) + ",\n";
  j += " \"units\": \"mm\",\n";
  j += " \"generator\": \"ausbau-scene-gen (common/scene/box_scenes.cpp)\",\n";
  j += " \"description\": " + JsonString(scene.description) + ",\n";
  j += std::string(" \"tessellation\": \"") + (tess == BoxTessellation::kFine ? "fine" : "coarse") + "\",\n";
  j += std::string(" \"world\": \"") + (scene.options.world == BoxWorld::kRandom ? "random" : "identity") + "\",\n";
  j += " \"world_placement\": {\"convention\": \"design frame (S's plate top z = 0, pull +z) to world: "
       "x_world = R(q) x + t\", \"q_wxyz\": [" +
       Num(scene.world.q.w()) + ", " + Num(scene.world.q.x()) + ", " + Num(scene.world.q.y()) + ", " +
       Num(scene.world.q.z()) + "], \"t\": " + JsonVec(scene.world.t) + "},\n";
  j += " \"pull_direction_world\": " + JsonVec(scene.pull_direction) + ",\n";
  j += " \"files\": {\"static\": \"static.stl\", \"dynamic\": \"dynamic.stl\", \"dynamic_rigid\": "
       "\"truth/dynamic_rigid.stl\", ";
  if (!clips.empty()) j += "\"dynamic_clips\": \"truth/dynamic_clips.stl\", ";
  j += "\"labels\": \"truth/labels_per_triangle.txt\", \"known_path\": \"truth/known_path.csv\", \"boxes\": "
       "\"boxes.json\"},\n";
  j += " \"installed_pose\": {\"x\": 0.0, \"y\": 0.0, \"z\": 0.0, \"qw\": 1.0, \"qx\": 0.0, \"qy\": 0.0, \"qz\": "
       "0.0},\n";
  j += " \"pose_convention\": \"p_world = R(q) @ p + (x,y,z) for every vertex p of dynamic*.stl; between waypoints "
       "translation is lerped and rotation slerped\",\n";
  j += " \"success\": \"last pose: world AABB of D disjoint from world AABB of S; no rigid box of D penetrates S by "
       "more than 0.05 mm anywhere along the path; clips may intersect S\",\n";
  j += " \"parameters\": {";
  for (size_t k = 0; k < scene.parameters.size(); ++k) {
    j +=
        (k == 0 ? "\n  " : ",\n  ") + JsonString(scene.parameters[k].first) + ": " + Num(scene.parameters[k].second, g);
  }
  j += "\n },\n";
  j += " \"known_path\": {\"motions\": " + JsonString(scene.path_summary) +
       ", \"waypoints\": " + std::to_string(scene.path.size()) + ", \"translation_mm\": " + Num(length, g) +
       ", \"rotation_deg\": " + Num(angle / kDeg, g) + ", \"min_rigid_separation_mm\": " + Num(path_separation, g) +
       "},\n";
  j += " \"installed_state\": {\"rigid_min_clearance_mm\": " + Num(contacts.rigid_min_clearance, g) +
       ", \"design_min_clearance_mm\": " + Num(scene.min_clearance, g) + ", \"clips\": " + std::to_string(scene.clips) +
       ", \"clips_intersect_static\": " + (all_clips_intersect ? "true" : "false") +
       ", \"clip_static_overlapping_box_pairs\": " + std::to_string(contacts.clip_static_overlapping_pairs) +
       ", \"max_clip_penetration_mm\": " + Num(contacts.max_clip_penetration, g) + "},\n";
  j += " \"counts\": {\"static_boxes\": " + std::to_string(scene.static_boxes.size()) +
       ", \"dynamic_rigid_boxes\": " + std::to_string(scene.rigid_boxes.size()) +
       ", \"dynamic_clip_boxes\": " + std::to_string(scene.clip_boxes.size()) +
       ", \"static_triangles\": " + std::to_string(s_triangles) +
       ", \"dynamic_triangles\": " + std::to_string(d_triangles) + "}\n";
  j += "}\n";
  WriteTextFileAtomically(files.scene_json, j);
  return files;
}

BoxSceneFiles GenerateBoxScene(const std::string& family, const BoxSceneOptions& options, const fs::path& dir) {
  return WriteBoxScene(BuildBoxScene(family, options), dir);
}

}  // namespace ausbau
