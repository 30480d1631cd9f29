#include "scene/clip_scenes.h"

#include <yaml-cpp/yaml.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <functional>
#include <sstream>
#include <stdexcept>

#include "core/atomic_file.h"
#include "core/error.h"
#include "geometry/primitives.h"
#include "planning/random.h"
#include "scene/mesh_io.h"
#include "scene/scene.h"

namespace ausbau {
namespace {

namespace fs = std::filesystem;
using Vec3 = Eigen::Vector3d;

constexpr char kGroundTruthFormat[] = "ausbau-clip-ground-truth/1";

// Fixed dimensions (mm).
constexpr double kPanelThickness = 2.5;
constexpr double kPlateThickness = 2.0;
constexpr double kPlateMargin = 25.0;       // S's plate reaches this far beyond the panel
constexpr double kRigidClearance = 3.0;     // between rigid parts of D and S
constexpr double kClipSideClearance = 1.5;  // tongue to the hole's ends
constexpr double kBendRoom = 1.5;           // hole room behind the tongue beyond the barb's overlap
constexpr double kLiftMargin = 4.0;         // barbs this far above S's top at the clear waypoint
constexpr double kRimWidth = 2.0;
constexpr double kFrictionInterference = 0.3;  // ds4: the rails' feet reach this far into the lips

// ---------------------------------------------------------------- meshes

double SignedVolume(const TriangleMesh& m) {
  double v = 0;
  for (const auto& t : m.triangles) {
    v += m.vertices[t[0]].dot(m.vertices[t[1]].cross(m.vertices[t[2]]));
  }
  return v / 6.0;
}

// Two triangles a-b-c, a-c-d, oriented so that their normal points along
// `outward`.
void AddQuad(TriangleMesh* m, int a, int b, int c, int d, const Vec3& outward) {
  const Vec3 n = (m->vertices[b] - m->vertices[a]).cross(m->vertices[c] - m->vertices[a]);
  if (n.dot(outward) >= 0) {
    m->triangles.push_back({a, b, c});
    m->triangles.push_back({a, c, d});
  } else {
    m->triangles.push_back({a, c, b});
    m->triangles.push_back({a, d, c});
  }
}

// A watertight slab over the grid xs x ys (sorted breakpoints): cell (i, j)
// is solid where solid(i, j); z in [z0, z1] shifted by dz(x). Top, bottom and
// walls share the grid's vertices, so there are no T-junctions.
TriangleMesh MakeGridSolid(const std::vector<double>& xs, const std::vector<double>& ys, double z0, double z1,
                           const std::function<bool(int, int)>& solid, const std::function<double(double)>& dz) {
  const int nx = static_cast<int>(xs.size()) - 1, ny = static_cast<int>(ys.size()) - 1;
  TriangleMesh m;
  std::vector<int> top((nx + 1) * (ny + 1), -1), bottom((nx + 1) * (ny + 1), -1);
  auto node = [&](std::vector<int>& ids, int i, int j, double z) {
    int& id = ids[j * (nx + 1) + i];
    if (id < 0) {
      id = static_cast<int>(m.vertices.size());
      m.vertices.emplace_back(xs[i], ys[j], z + dz(xs[i]));
    }
    return id;
  };
  auto T = [&](int i, int j) { return node(top, i, j, z1); };
  auto B = [&](int i, int j) { return node(bottom, i, j, z0); };
  auto is_solid = [&](int i, int j) { return i >= 0 && j >= 0 && i < nx && j < ny && solid(i, j); };
  for (int j = 0; j < ny; ++j) {
    for (int i = 0; i < nx; ++i) {
      if (!solid(i, j)) continue;
      AddQuad(&m, T(i, j), T(i + 1, j), T(i + 1, j + 1), T(i, j + 1), Vec3::UnitZ());
      AddQuad(&m, B(i, j), B(i + 1, j), B(i + 1, j + 1), B(i, j + 1), -Vec3::UnitZ());
      if (!is_solid(i - 1, j)) AddQuad(&m, B(i, j), B(i, j + 1), T(i, j + 1), T(i, j), -Vec3::UnitX());
      if (!is_solid(i + 1, j)) AddQuad(&m, B(i + 1, j), B(i + 1, j + 1), T(i + 1, j + 1), T(i + 1, j), Vec3::UnitX());
      if (!is_solid(i, j - 1)) AddQuad(&m, B(i, j), B(i + 1, j), T(i + 1, j), T(i, j), -Vec3::UnitY());
      if (!is_solid(i, j + 1)) AddQuad(&m, B(i, j + 1), B(i + 1, j + 1), T(i + 1, j + 1), T(i, j + 1), Vec3::UnitY());
    }
  }
  return m;
}

std::vector<double> Uniform(double a, double b, int cells) {
  std::vector<double> out;
  for (int k = 0; k <= cells; ++k) out.push_back(k == cells ? b : a + (b - a) * k / cells);
  return out;
}

// Sorted breakpoints: `base` plus `cells` uniform cells over [base.front(),
// base.back()], dropping uniform points closer than 0.05 to a base point.
std::vector<double> Breakpoints(std::vector<double> base, int cells) {
  std::sort(base.begin(), base.end());
  base.erase(std::unique(base.begin(), base.end(), [](double a, double b) { return std::abs(a - b) < 1e-9; }),
             base.end());
  std::vector<double> out = base;
  if (cells > 1) {
    for (double x : Uniform(base.front(), base.back(), cells)) {
      const auto it = std::lower_bound(base.begin(), base.end(), x);
      const double near =
          std::min(it == base.end() ? 1e300 : std::abs(*it - x), it == base.begin() ? 1e300 : std::abs(*(it - 1) - x));
      if (near >= 0.05) out.push_back(x);
    }
    std::sort(out.begin(), out.end());
  }
  return out;
}

// A convex prism: polygon (u, v) extruded over w in [w0, w1]; map(u, v, w)
// places it. Faces are oriented away from the prism's centroid.
TriangleMesh MakePrism(const std::vector<Eigen::Vector2d>& polygon, double w0, double w1,
                       const std::function<Vec3(double, double, double)>& map) {
  TriangleMesh m;
  const int n = static_cast<int>(polygon.size());
  for (double w : {w0, w1}) {
    for (const auto& p : polygon) m.vertices.push_back(map(p.x(), p.y(), w));
  }
  Vec3 centroid = Vec3::Zero();
  for (const auto& v : m.vertices) centroid += v;
  centroid /= m.vertices.size();
  auto add_tri = [&](int a, int b, int c) {
    const Vec3 n3 = (m.vertices[b] - m.vertices[a]).cross(m.vertices[c] - m.vertices[a]);
    const Vec3 out = (m.vertices[a] + m.vertices[b] + m.vertices[c]) / 3.0 - centroid;
    if (n3.dot(out) >= 0)
      m.triangles.push_back({a, b, c});
    else
      m.triangles.push_back({a, c, b});
  };
  for (int k = 1; k + 1 < n; ++k) {
    add_tri(0, k, k + 1);
    add_tri(n, n + k, n + k + 1);
  }
  for (int k = 0; k < n; ++k) {
    const int k1 = (k + 1) % n;
    const Vec3 out = (m.vertices[k] + m.vertices[k1] + m.vertices[n + k] + m.vertices[n + k1]) / 4.0 - centroid;
    AddQuad(&m, k, k1, n + k1, n + k, out);
  }
  return m;
}

// Area of the polygon clipped to a u >= u_min, z in [z0, z1] (Sutherland-Hodgman).
double ClippedArea(std::vector<Eigen::Vector2d> poly, double u_min, double z0, double z1) {
  auto clip = [&](const std::function<double(const Eigen::Vector2d&)>& f) {  // keep f >= 0
    std::vector<Eigen::Vector2d> out;
    for (size_t k = 0; k < poly.size(); ++k) {
      const Eigen::Vector2d& a = poly[k];
      const Eigen::Vector2d& b = poly[(k + 1) % poly.size()];
      const double fa = f(a), fb = f(b);
      if (fa >= 0) out.push_back(a);
      if ((fa >= 0) != (fb >= 0)) out.push_back(a + (b - a) * (fa / (fa - fb)));
    }
    poly = out;
  };
  clip([&](const Eigen::Vector2d& p) { return p.x() - u_min; });
  clip([&](const Eigen::Vector2d& p) { return p.y() - z0; });
  clip([&](const Eigen::Vector2d& p) { return z1 - p.y(); });
  double area = 0;
  for (size_t k = 0; k < poly.size(); ++k) {
    const auto& a = poly[k];
    const auto& b = poly[(k + 1) % poly.size()];
    area += a.x() * b.y() - b.x() * a.y();
  }
  return std::abs(area) / 2;
}

// ---------------------------------------------------------------- families

struct ClipSpec {
  double width, thickness, barb, clearance, barb_height, penetration, deformability;
};

struct RailSpec {
  char shape;         // 'L' (foot under a lip bracket) or 'T' (head under the plate, keyhole slot)
  double length;      // L: along y; T: along x
  double leg;         // leg thickness
  double foot;        // L: foot thickness; T: head thickness
  double engage;      // L: how far the foot reaches under the overhang
  double over;        // L: overhang thickness
  double head_width;  // T: head width in y
};

struct FamilySpec {
  double half_x, half_y;
  int clips;
  ClipSpec clip;
  std::vector<RailSpec> rails;
  bool friction;
  double rim_probability, max_rise;
  std::int64_t table_d, table_s;  // thesis table 14
  std::string description;
};

const ClipSpec kSmallClip{8.0, 1.2, 1.6, 0.6, 3.0, 0.6, 1.0};
const ClipSpec kLargeClip{16.0, 2.0, 3.2, 0.8, 5.0, 1.0, 1.0};
const ClipSpec kThickClip{10.0, 4.0, 1.4, 0.5, 3.0, 0.6, 0.35};
const RailSpec kSmallL{'L', 10.0, 3.0, 2.0, 3.0, 2.0, 0};
const RailSpec kSmallT{'T', 9.0, 3.0, 2.0, 0, 0, 12.0};

FamilySpec Family(const std::string& family) {
  if (family == "clips-ds1") {
    return {110,
            65,
            8,
            kSmallClip,
            {kSmallL},
            false,
            0.5,
            2.0,
            67134,
            43918,
            "8 small clips + 1 L-rail: the clips' summed overlap exceeds the rail's; slide -x, then lift"};
  }
  if (family == "clips-ds2") {
    return {100,
            60,
            3,
            kSmallClip,
            {kSmallL},
            false,
            0.5,
            2.0,
            48308,
            26364,
            "3 small clips + 1 L-rail: the clips' overlap is small; slide -x, then lift"};
  }
  if (family == "clips-ds3") {
    RailSpec l = kSmallL;
    l.length = 8.0;
    return {
        90,
        55,
        6,
        kLargeClip,
        {l, kSmallT},
        false,
        0.5,
        2.0,
        6544,
        26430,
        "6 large clips + 2 rails (L under a lip, T in a keyhole slot), clips bigger than rails; slide -x, then lift"};
  }
  if (family == "clips-ds4") {
    RailSpec l = kSmallL;
    l.length = 14.0;
    return {80,
            45,
            2,
            kSmallClip,
            {l, l},
            true,
            0.0,
            0.0,
            2448,
            4250,
            "2 small clips + 2 L-rails in a friction fit (their feet intersect the lips); slide -x, then lift"};
  }
  if (family == "clips-ds5") {
    return {90,
            55,
            4,
            kThickClip,
            {},
            false,
            0.0,
            0.0,
            26290,
            16810,
            "4 thick, nearly rigid clips, no rails: a straight pull-out in +z"};
  }
  throw InputError("--family: unknown family '" + family + "' (expected clips-ds1 .. clips-ds5)");
}

struct PartRecord {
  ClipScenePart part;
  std::int64_t tri_begin = 0, tri_end = 0;
};

struct Hole {
  double x0, x1, y0, y1;
};

struct Built {
  TriangleMesh dynamic, environment;
  std::vector<PartRecord> parts;
  ClipGroundTruth truth;
  std::string description;
};

class Generator {
 public:
  Generator(const std::string& family, std::uint64_t seed) : spec_(Family(family)), random_(seed) {
    // Everything random is drawn here, once, so that tessellation changes
    // nothing but the triangle count.
    half_x_ = spec_.half_x * random_.Uniform(0.95, 1.05);
    half_y_ = spec_.half_y * random_.Uniform(0.95, 1.05);
    rim_ = random_.Uniform01() < spec_.rim_probability;
    rise_ = spec_.max_rise > 0 ? random_.Uniform(0.0, spec_.max_rise) : 0.0;
    clip_ = spec_.clip;
    clip_.width *= random_.Uniform(0.95, 1.05);
    clip_.barb *= random_.Uniform(0.97, 1.03);
    clip_.barb_height *= random_.Uniform(0.95, 1.05);
    for (int k = 0; k < spec_.clips; ++k) clip_jitter_.push_back(random_.Uniform(-3.0, 3.0));
    for (size_t k = 0; k < spec_.rails.size(); ++k) rail_x_.push_back(random_.Uniform(-0.2, 0.05) * half_x_);

    // Heights: the lips' tops stay kRigidClearance below the panel.
    double lip_top = 0;
    for (const RailSpec& r : spec_.rails) {
      if (r.shape == 'L') lip_top = std::max(lip_top, LipBottom(r) + r.over);
    }
    gap_ = lip_top > 0 ? lip_top + kRigidClearance : 6.0;
    slide_ = 0;
    for (const RailSpec& r : spec_.rails) {
      slide_ = std::max(slide_, r.shape == 'L' ? r.engage + kRigidClearance + 1.0 : r.length + kRigidClearance + 1.0);
    }
  }

  Built Build(int panel_cells_y, int plate_cells_y) {
    Built out;
    auto dz = [&](double x) { return rise_ * (x / half_x_) * (x / half_x_); };
    auto flat = [](double) { return 0.0; };
    const double panel_mid = gap_ + kPanelThickness / 2;
    std::vector<Hole> holes;
    ClipGroundTruth& truth = out.truth;
    truth.slide = slide_;
    truth.friction = spec_.friction;

    auto add_part = [&](const std::string& name, const std::string& kind, double deformability,
                        const TriangleMesh& mesh) -> ClipScenePart& {
      PartRecord rec;
      rec.part.name = name;
      rec.part.kind = kind;
      rec.part.deformable = kind == "clip";
      rec.part.deformability = deformability;
      rec.part.volume = SignedVolume(mesh);
      rec.tri_begin = static_cast<std::int64_t>(out.dynamic.triangles.size());
      out.dynamic.Append(mesh);
      rec.tri_end = static_cast<std::int64_t>(out.dynamic.triangles.size());
      out.parts.push_back(rec);
      return out.parts.back().part;
    };

    // The panel.
    const int ny = std::max(1, panel_cells_y);
    const int nx = std::max(1, static_cast<int>(std::lround(ny * half_x_ / half_y_)));
    const std::vector<double> pxs = Uniform(-half_x_, half_x_, nx), pys = Uniform(-half_y_, half_y_, ny);
    add_part("panel", "panel", 0.0,
             MakeGridSolid(
                 pxs, pys, gap_, gap_ + kPanelThickness, [](int, int) { return true; }, dz));
    if (rim_) {
      // A skirt along the edges, from the panel's mid-plane down to
      // kRigidClearance above S's top; it follows the panel's curvature.
      TriangleMesh rim;
      const double z0 = kRigidClearance, z1 = panel_mid;
      auto all = [](int, int) { return true; };
      rim.Append(MakeGridSolid(pxs, {-half_y_, -half_y_ + kRimWidth}, z0, z1, all, dz));
      rim.Append(MakeGridSolid(pxs, {half_y_ - kRimWidth, half_y_}, z0, z1, all, dz));
      const std::vector<double> inner_ys(pys.begin(), pys.end());
      rim.Append(MakeGridSolid({-half_x_, -half_x_ + kRimWidth}, inner_ys, z0, z1, all, dz));
      rim.Append(MakeGridSolid({half_x_ - kRimWidth, half_x_}, inner_ys, z0, z1, all, dz));
      add_part("rim", "rim", 0.0, rim);
    }

    // Clips, in two rows near the long edges, barbs pointing outwards.
    const double row = half_y_ - 12.0;
    const int n_top = (spec_.clips + 1) / 2;
    const double o = clip_.barb - clip_.clearance;  // overlap beyond the hole's rim
    const double z_barb_top = -kPlateThickness + clip_.penetration;
    const double z_tip = z_barb_top - clip_.barb_height;
    double lowest = z_tip;
    // The barb's profile: u = outward from the tongue's outer face, v = z.
    const std::vector<Eigen::Vector2d> profile = {{-clip_.thickness / 2, z_tip},
                                                  {0.25 * clip_.barb, z_tip},
                                                  {clip_.barb, z_barb_top - 0.35 * clip_.barb_height},
                                                  {clip_.barb, z_barb_top},
                                                  {-clip_.thickness / 2, z_barb_top}};
    double pull = 0;  // largest overlap of one barb while it is lifted through
    for (int s = 0; s <= 2000; ++s) {
      const double lift = (z_barb_top - z_tip + kPlateThickness) * s / 2000.0;
      std::vector<Eigen::Vector2d> lifted = profile;
      for (auto& p : lifted) p.y() += lift;
      pull = std::max(pull, ClippedArea(lifted, clip_.clearance, -kPlateThickness, 0.0) * clip_.width);
    }
    for (int k = 0; k < spec_.clips; ++k) {
      const bool top_row = k < n_top;
      const int index = top_row ? k : k - n_top;
      const int count = top_row ? n_top : spec_.clips - n_top;
      const double x_lo = -half_x_ + 22.0, x_hi = half_x_ - 22.0;
      // Evenly spread, the two rows staggered, jittered by the seed.
      const double xc = x_lo + (x_hi - x_lo) * (index + (top_row ? 0.3 : 0.7)) / count + clip_jitter_[k];
      const double sign = top_row ? 1.0 : -1.0;
      const double yc = sign * row;
      const double outer = yc + sign * clip_.thickness / 2;  // the tongue's outer face
      const double w = clip_.width;
      TriangleMesh clip = MakeBox({xc - w / 2, yc - clip_.thickness / 2, z_tip},
                                  {xc + w / 2, yc + clip_.thickness / 2, panel_mid + dz(xc)});
      clip.Append(MakePrism(profile, xc - w / 2, xc + w / 2,
                            [&](double u, double v, double x) { return Vec3(x, outer + sign * u, v); }));
      ClipScenePart& part = add_part("clip-" + std::to_string(k), "clip", clip_.deformability, clip);
      const double edge = outer + sign * clip_.clearance;  // the hole's rim the barb hooks behind
      part.overlap_box.Extend(Vec3(xc - w / 2, edge, -kPlateThickness));
      part.overlap_box.Extend(Vec3(xc + w / 2, outer + sign * clip_.barb, z_barb_top));
      const double inner = yc - sign * (clip_.thickness / 2 + o + kBendRoom);
      holes.push_back({xc - w / 2 - kClipSideClearance - slide_, xc + w / 2 + kClipSideClearance, std::min(edge, inner),
                       std::max(edge, inner)});
      truth.clip_pull_overlap += pull;
    }

    // Rails (and the lips or slots of S that hold them).
    TriangleMesh lips;
    double rail_y_single = 0;
    for (size_t k = 0; k < spec_.rails.size(); ++k) {
      const RailSpec& r = spec_.rails[k];
      const double yr = spec_.rails.size() == 1 ? rail_y_single : (k == 0 ? -1 : 1) * 0.3 * half_y_;
      const double xr = rail_x_[k];
      TriangleMesh rail;
      Aabb friction_box;
      if (r.shape == 'L') {
        const double foot_z0 = kRigidClearance, foot_z1 = foot_z0 + r.foot;
        const double x_over0 = xr + r.leg + kRigidClearance;  // the overhang's free end
        const double x_foot1 = x_over0 + r.engage;            // the foot's end
        const double x_post0 = x_foot1 + kRigidClearance, x_post1 = x_post0 + 3.0;
        const double z_over0 = LipBottom(r), z_over1 = z_over0 + r.over;
        rail.Append(MakeBox({xr, yr - r.length / 2, foot_z0}, {xr + r.leg, yr + r.length / 2, panel_mid + dz(xr)}));
        rail.Append(MakeBox({xr, yr - r.length / 2, foot_z0}, {x_foot1, yr + r.length / 2, foot_z1}));
        lips.Append(
            MakeBox({x_post0, yr - r.length / 2 - 2, -kPlateThickness / 2}, {x_post1, yr + r.length / 2 + 2, z_over1}));
        lips.Append(MakeBox({x_over0, yr - r.length / 2 - 2, z_over0}, {x_post1, yr + r.length / 2 + 2, z_over1}));
        truth.rail_block_overlap += r.engage * r.length * std::min(r.foot, r.over);
        if (spec_.friction) {
          friction_box.Extend(Vec3(x_over0, yr - r.length / 2, z_over0));
          friction_box.Extend(Vec3(x_foot1, yr + r.length / 2, foot_z1));
        }
      } else {
        const double head_z1 = -kPlateThickness - kRigidClearance, head_z0 = head_z1 - r.foot;
        rail.Append(MakeBox({xr, yr - r.head_width / 2, head_z0}, {xr + r.length, yr + r.head_width / 2, head_z1}));
        rail.Append(MakeBox({xr, yr - r.leg / 2, head_z0}, {xr + r.length, yr + r.leg / 2, panel_mid + dz(xr)}));
        // Keyhole: a narrow slot for the leg, wide enough for the head once
        // D has slid by `slide_`.
        const double narrow = r.leg / 2 + kRigidClearance, wide = r.head_width / 2 + kRigidClearance;
        holes.push_back({xr - slide_ - kRigidClearance, xr + r.length + kRigidClearance, yr - narrow, yr + narrow});
        holes.push_back(
            {xr - slide_ - kRigidClearance, xr - slide_ + r.length + kRigidClearance, yr - wide, yr + wide});
        lowest = std::min(lowest, head_z0);
        const double slot = r.leg + 2 * kRigidClearance;
        truth.rail_block_overlap += (r.head_width - slot) * r.length * std::min(r.foot, kPlateThickness);
      }
      ClipScenePart& part = add_part("rail-" + std::to_string(k), "rail", 0.0, rail);
      part.overlap_box = friction_box;
    }

    // S: the base plate with its holes, tessellated on the holes' breakpoints,
    // plus the lips.
    const double sx = half_x_ + kPlateMargin, sy = half_y_ + kPlateMargin;
    std::vector<double> bx = {-sx, sx}, by = {-sy, sy};
    for (const Hole& h : holes) {
      bx.insert(bx.end(), {h.x0, h.x1});
      by.insert(by.end(), {h.y0, h.y1});
    }
    const int plate_cells_x = std::max(1, static_cast<int>(std::lround(plate_cells_y * sx / sy)));
    const std::vector<double> sxs = Breakpoints(bx, plate_cells_x), sys = Breakpoints(by, plate_cells_y);
    auto solid = [&](int i, int j) {
      const double cx = 0.5 * (sxs[i] + sxs[i + 1]), cy = 0.5 * (sys[j] + sys[j + 1]);
      for (const Hole& h : holes) {
        if (cx > h.x0 && cx < h.x1 && cy > h.y0 && cy < h.y1) return false;
      }
      return true;
    };
    out.environment = MakeGridSolid(sxs, sys, -kPlateThickness, 0.0, solid, flat);
    out.environment.Append(lips);

    // Ground truth: origin, path.
    truth.dynamic_origin = Vec3(0, 0, panel_mid);
    truth.lift_clear = -lowest + kLiftMargin;
    const Aabb d_box = out.dynamic.Bounds(), s_box = out.environment.Bounds();
    const double away = std::max(truth.lift_clear + 5.0, s_box.max.z() - d_box.min.z() + 10.0);
    Pose p;
    p.t = truth.dynamic_origin;
    truth.path.push_back(p);
    if (slide_ > 0) {
      p.t.x() -= slide_;
      truth.path.push_back(p);
    }
    p.t.z() += truth.lift_clear;
    truth.path.push_back(p);
    truth.clear_waypoint = static_cast<int>(truth.path.size()) - 1;
    p.t.z() = truth.dynamic_origin.z() + away;
    truth.path.push_back(p);
    out.description = spec_.description;
    return out;
  }

  const FamilySpec& spec() const { return spec_; }

 private:
  double LipBottom(const RailSpec& r) const {
    const double foot_top = kRigidClearance + r.foot;
    return spec_.friction ? foot_top - kFrictionInterference : foot_top + kRigidClearance;
  }

  FamilySpec spec_;
  Random random_;
  double half_x_ = 0, half_y_ = 0, rise_ = 0, gap_ = 0, slide_ = 0;
  bool rim_ = false;
  ClipSpec clip_{};
  std::vector<double> clip_jitter_, rail_x_;
};

// ---------------------------------------------------------------- output

std::vector<IndexRange> ToRanges(std::vector<std::int64_t> ids) {
  std::sort(ids.begin(), ids.end());
  ids.erase(std::unique(ids.begin(), ids.end()), ids.end());
  std::vector<IndexRange> out;
  for (std::int64_t id : ids) {
    if (!out.empty() && out.back().end == id) {
      ++out.back().end;
    } else {
      out.push_back({id, id + 1});
    }
  }
  return out;
}

std::string Num(double v) {
  char buf[64];
  std::snprintf(buf, sizeof buf, "%.17g", v);
  return buf;
}

std::string RangesYaml(const std::vector<IndexRange>& ranges) {
  std::string y = "[";
  for (size_t k = 0; k < ranges.size(); ++k) {
    if (k > 0) y += ", ";
    y += "[" + std::to_string(ranges[k].begin) + ", " + std::to_string(ranges[k].end) + "]";
  }
  return y + "]";
}

std::string VecYaml(const Vec3& v) { return "[" + Num(v.x()) + ", " + Num(v.y()) + ", " + Num(v.z()) + "]"; }

std::string PathCsv(const std::vector<Pose>& path) {
  std::string text = "x,y,z,qw,qx,qy,qz\n";
  for (const Pose& p : path) {
    text += Num(p.t.x()) + "," + Num(p.t.y()) + "," + Num(p.t.z()) + "," + Num(p.q.w()) + "," + Num(p.q.x()) + "," +
            Num(p.q.y()) + "," + Num(p.q.z()) + "\n";
  }
  return text;
}

std::vector<IndexRange> Union(const std::vector<ClipScenePart>& parts, bool clips, bool triangles) {
  std::vector<std::int64_t> ids;
  for (const auto& part : parts) {
    if (part.deformable != clips) continue;
    for (const IndexRange& r : triangles ? part.triangles : part.vertices) {
      for (std::int64_t i = r.begin; i < r.end; ++i) ids.push_back(i);
    }
  }
  return ToRanges(ids);
}

std::string GroundTruthYaml(const ClipGroundTruth& t, const std::string& description) {
  std::string y;
  y += "# Ground truth of a generated InIState scene (common/scene/clip_scenes.h).\n";
  y += "# Index ranges are [begin, end) into D (part.obj) as ausbau's LoadMesh returns it:\n";
  y += "# triangles in file order, vertices after assimp's joining of identical vertices.\n";
  y += std::string("format: ") + kGroundTruthFormat + "\n";
  y += "family: " + t.family + "\n";
  y += "seed: " + std::to_string(t.seed) + "\n";
  y += "units: mm\n";
  y += "description: \"" + description + "\"\n";
  y += "dynamic: {file: part.obj, triangles: " + std::to_string(t.dynamic_triangles) +
       ", vertices: " + std::to_string(t.dynamic_vertices) + "}\n";
  y += "static: {file: environment.obj, triangles: " + std::to_string(t.static_triangles) + "}\n";
  y += "dynamic_origin: " + VecYaml(t.dynamic_origin) + "\n";
  y += "clip_triangles: " + RangesYaml(Union(t.parts, true, true)) + "\n";
  y += "clip_vertices: " + RangesYaml(Union(t.parts, true, false)) + "\n";
  y += "rigid_triangles: " + RangesYaml(Union(t.parts, false, true)) + "\n";
  y += "rigid_vertices: " + RangesYaml(Union(t.parts, false, false)) + "\n";
  y += "overlap:\n";
  y += "  clip_pull: " + Num(t.clip_pull_overlap) +
       "    # mm^3: summed over clips, the largest barb/plate overlap while pulled through\n";
  y += "  rail_block: " + Num(t.rail_block_overlap) +
       "   # mm^3: what the rails would overlap S if D were lifted without sliding\n";
  y += std::string("  friction: ") + (t.friction ? "true" : "false") +
       "   # rigid rails overlap S until they leave their lips (ds4)\n";
  y += "parts:\n";
  for (const auto& p : t.parts) {
    y += "  - name: " + p.name + "\n";
    y += "    kind: " + p.kind + "\n";
    y += std::string("    deformable: ") + (p.deformable ? "true" : "false") + "\n";
    y += "    deformability: " + Num(p.deformability) + "\n";
    y += "    volume: " + Num(p.volume) + "\n";
    y += "    triangles: " + RangesYaml(p.triangles) + "\n";
    y += "    vertices: " + RangesYaml(p.vertices) + "\n";
    if (!p.overlap_box.Empty()) {
      y += "    overlap_box: {min: " + VecYaml(p.overlap_box.min) + ", max: " + VecYaml(p.overlap_box.max) + "}\n";
    }
  }
  y += "path:\n";
  y += "  file: ground_truth_path.csv   # x,y,z,qw,qx,qy,qz, scene convention\n";
  y += "  waypoints: " + std::to_string(t.path.size()) + "\n";
  y += "  slide: " + Num(t.slide) + "        # first -x by this much (0: none)\n";
  y += "  lift_clear: " + Num(t.lift_clear) + "   # then +z by this much: the clips are through\n";
  y += "  clear_waypoint: " + std::to_string(t.clear_waypoint) + "   # first waypoint where D overlaps S no more\n";
  return y;
}

}  // namespace

std::vector<std::string> ClipSceneFamilies() {
  return {"clips-ds1", "clips-ds2", "clips-ds3", "clips-ds4", "clips-ds5"};
}

bool IsClipSceneFamily(const std::string& family) {
  const auto f = ClipSceneFamilies();
  return std::find(f.begin(), f.end(), family) != f.end();
}

std::vector<double> ClipGroundTruth::VertexDeformability() const {
  std::vector<double> out(static_cast<size_t>(dynamic_vertices), 0.0);
  for (const auto& part : parts) {
    for (const IndexRange& r : part.vertices) {
      for (std::int64_t i = r.begin; i < r.end && i < dynamic_vertices; ++i) {
        out[i] = std::max(out[i], part.deformability);
      }
    }
  }
  return out;
}

std::vector<bool> ClipGroundTruth::ClipTriangleMask() const {
  std::vector<bool> out(static_cast<size_t>(dynamic_triangles), false);
  for (const auto& part : parts) {
    if (!part.deformable) continue;
    for (const IndexRange& r : part.triangles) {
      for (std::int64_t i = r.begin; i < r.end && i < dynamic_triangles; ++i) out[i] = true;
    }
  }
  return out;
}

ClipSceneFiles GenerateClipScene(const std::string& family, const ClipSceneOptions& options, const fs::path& dir) {
  if (options.triangles < 0 || options.triangles > 2000000) {
    throw InputError("--triangles: must lie in [0, 2000000] (got " + std::to_string(options.triangles) + ")");
  }
  Generator generator(family, options.seed);
  const FamilySpec& spec = generator.spec();
  const std::int64_t target_d = options.triangles > 0 ? options.triangles : spec.table_d;
  const std::int64_t target_s = options.triangles > 0
                                    ? std::llround(static_cast<double>(options.triangles) * spec.table_s / spec.table_d)
                                    : spec.table_s;

  // The triangle count grows monotonically with the cell counts: bisect each.
  auto closest = [](const std::function<std::int64_t(int)>& count, std::int64_t target) {
    int lo = 1, hi = 1;
    while (count(hi) < target && hi < (1 << 14)) hi *= 2;
    while (hi - lo > 1) {
      const int mid = (lo + hi) / 2;
      (count(mid) < target ? lo : hi) = mid;
    }
    return std::abs(count(lo) - target) <= std::abs(count(hi) - target) ? lo : hi;
  };
  const int panel_cells = closest(
      [&](int n) { return static_cast<std::int64_t>(generator.Build(n, 1).dynamic.triangles.size()); }, target_d);
  const int plate_cells = closest(
      [&](int n) { return static_cast<std::int64_t>(generator.Build(1, n).environment.triangles.size()); }, target_s);
  Built built = generator.Build(panel_cells, plate_cells);

  fs::create_directories(dir);
  ClipSceneFiles files;
  files.scene_yaml = dir / "scene.yaml";
  files.ground_truth_yaml = dir / "ground_truth.yaml";
  files.ground_truth_path = dir / "ground_truth_path.csv";
  Scene scene;
  scene.name = family + "-" + std::to_string(options.seed);
  scene.units = "mm";
  scene.static_files = {dir / "environment.obj"};
  scene.dynamic_file = dir / "part.obj";
  scene.dynamic_origin = built.truth.dynamic_origin;
  scene.dynamic_origin_given = true;
  scene.start = built.truth.path.front();
  SaveObj(built.environment, scene.static_files[0]);
  SaveObj(built.dynamic, scene.dynamic_file);
  SaveSceneYaml(scene, files.scene_yaml);

  // Vertex indices as the loader will number them.
  const TriangleMesh loaded = LoadMesh(scene.dynamic_file);
  if (loaded.triangles.size() != built.dynamic.triangles.size()) {
    throw std::logic_error(scene.dynamic_file.string() + ": the loader changed the triangle count (" +
                           std::to_string(built.dynamic.triangles.size()) + " written, " +
                           std::to_string(loaded.triangles.size()) + " read)");
  }
  ClipGroundTruth& truth = built.truth;
  truth.family = family;
  truth.seed = options.seed;
  truth.dynamic_triangles = static_cast<std::int64_t>(loaded.triangles.size());
  truth.dynamic_vertices = static_cast<std::int64_t>(loaded.vertices.size());
  truth.static_triangles = static_cast<std::int64_t>(built.environment.triangles.size());
  for (PartRecord& rec : built.parts) {
    rec.part.triangles = {{rec.tri_begin, rec.tri_end}};
    std::vector<std::int64_t> ids;
    for (std::int64_t t = rec.tri_begin; t < rec.tri_end; ++t) {
      for (int v : loaded.triangles[t]) ids.push_back(v);
    }
    rec.part.vertices = ToRanges(ids);
    truth.parts.push_back(rec.part);
  }
  WriteTextFileAtomically(files.ground_truth_path, PathCsv(truth.path));
  WriteTextFileAtomically(files.ground_truth_yaml, GroundTruthYaml(truth, built.description));
  return files;
}

namespace {

std::vector<IndexRange> ReadRanges(const YAML::Node& node, const std::string& where) {
  std::vector<IndexRange> out;
  if (!node || !node.IsSequence()) throw InputErrorAt(where, "expected a list of [begin, end] ranges");
  for (const auto& r : node) {
    if (!r.IsSequence() || r.size() != 2) throw InputErrorAt(where, "expected [begin, end]");
    out.push_back({r[0].as<std::int64_t>(), r[1].as<std::int64_t>()});
  }
  return out;
}

Vec3 ReadVec(const YAML::Node& node, const std::string& where) {
  if (!node || !node.IsSequence() || node.size() != 3) throw InputErrorAt(where, "expected [x, y, z]");
  return {node[0].as<double>(), node[1].as<double>(), node[2].as<double>()};
}

std::vector<Pose> ReadPathCsv(const fs::path& file) {
  std::ifstream in(file);
  if (!in) throw InputErrorAt(file.string(), "file not found");
  std::string line;
  std::getline(in, line);
  if (line.rfind("x,y,z,qw,qx,qy,qz", 0) != 0)
    throw InputErrorAt(file.string(), "expected the header x,y,z,qw,qx,qy,qz");
  std::vector<Pose> path;
  while (std::getline(in, line)) {
    if (line.empty()) continue;
    std::stringstream ss(line);
    double v[7];
    char comma;
    for (int k = 0; k < 7; ++k) {
      if (!(ss >> v[k]) || (k < 6 && !(ss >> comma))) throw InputErrorAt(file.string(), "malformed row '" + line + "'");
    }
    Pose p;
    p.t = {v[0], v[1], v[2]};
    p.q = Eigen::Quaterniond(v[3], v[4], v[5], v[6]).normalized();
    path.push_back(p);
  }
  return path;
}

}  // namespace

ClipGroundTruth LoadClipGroundTruth(const fs::path& file) {
  const std::string where = file.string();
  YAML::Node root;
  try {
    root = YAML::LoadFile(where);
  } catch (const YAML::BadFile&) {
    throw InputErrorAt(where, "file not found");
  } catch (const YAML::Exception& e) {
    throw InputErrorAt(where, std::string("YAML error: ") + e.what());
  }
  try {
    if (!root["format"] || root["format"].as<std::string>() != kGroundTruthFormat) {
      throw InputErrorAt(where, std::string("expected format ") + kGroundTruthFormat);
    }
    ClipGroundTruth t;
    t.family = root["family"].as<std::string>();
    t.seed = root["seed"].as<std::uint64_t>();
    t.dynamic_triangles = root["dynamic"]["triangles"].as<std::int64_t>();
    t.dynamic_vertices = root["dynamic"]["vertices"].as<std::int64_t>();
    t.static_triangles = root["static"]["triangles"].as<std::int64_t>();
    t.dynamic_origin = ReadVec(root["dynamic_origin"], where + ": dynamic_origin");
    t.clip_pull_overlap = root["overlap"]["clip_pull"].as<double>();
    t.rail_block_overlap = root["overlap"]["rail_block"].as<double>();
    t.friction = root["overlap"]["friction"].as<bool>();
    for (const auto& p : root["parts"]) {
      ClipScenePart part;
      part.name = p["name"].as<std::string>();
      part.kind = p["kind"].as<std::string>();
      part.deformable = p["deformable"].as<bool>();
      part.deformability = p["deformability"].as<double>();
      part.volume = p["volume"].as<double>();
      part.triangles = ReadRanges(p["triangles"], where + ": parts." + part.name + ".triangles");
      part.vertices = ReadRanges(p["vertices"], where + ": parts." + part.name + ".vertices");
      if (p["overlap_box"]) {
        part.overlap_box.Extend(ReadVec(p["overlap_box"]["min"], where + ": overlap_box"));
        part.overlap_box.Extend(ReadVec(p["overlap_box"]["max"], where + ": overlap_box"));
      }
      t.parts.push_back(part);
    }
    const YAML::Node path = root["path"];
    t.slide = path["slide"].as<double>();
    t.lift_clear = path["lift_clear"].as<double>();
    t.clear_waypoint = path["clear_waypoint"].as<int>();
    t.path = ReadPathCsv(file.parent_path() / path["file"].as<std::string>());
    if (t.clear_waypoint < 0 || t.clear_waypoint >= static_cast<int>(t.path.size())) {
      throw InputErrorAt(where, "path.clear_waypoint is not a waypoint of the path");
    }
    return t;
  } catch (const YAML::Exception& e) {
    throw InputErrorAt(where, std::string("malformed ground truth: ") + e.what());
  }
}

}  // namespace ausbau
