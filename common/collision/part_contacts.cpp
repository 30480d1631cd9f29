#include "collision/part_contacts.h"

#include <fcl/narrowphase/collision.h>
#include <fcl/narrowphase/distance.h>

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <memory>

#include "collision/fcl_model.h"
#include "collision/mesh_depth.h"
#include "core/format.h"
#include "geometry/shells.h"

namespace ausbau {
namespace {

// The triangles of each part, as separate meshes (vertices copied per part).
std::vector<TriangleMesh> SplitParts(const TriangleMesh& environment, const std::vector<int>& part_of_triangle) {
  int count = 1;
  for (int part : part_of_triangle) count = std::max(count, part + 1);
  std::vector<TriangleMesh> parts(count);
  std::vector<std::vector<int>> new_index(count);
  for (std::size_t t = 0; t < environment.triangles.size(); ++t) {
    const int part = t < part_of_triangle.size() ? std::max(0, part_of_triangle[t]) : 0;
    TriangleMesh& mesh = parts[part];
    std::vector<int>& index = new_index[part];
    if (index.empty()) index.assign(environment.vertices.size(), -1);
    std::array<int, 3> triangle{};
    for (int k = 0; k < 3; ++k) {
      const int v = environment.triangles[t][k];
      if (index[v] < 0) {
        index[v] = static_cast<int>(mesh.vertices.size());
        mesh.vertices.push_back(environment.vertices[v]);
      }
      triangle[k] = index[v];
    }
    mesh.triangles.push_back(triangle);
  }
  return parts;
}

// The rigid check's depth of D in the part (collision/rigid_depth.h): the
// largest over pairs of D's shells and the part's whose boxes meet, the
// separating-axis depth where both are convex, else the surface depth (how
// far a point of either surface lies inside the other), to 0.01% of D's
// diagonal (beyond 1% of it, to 1/16 of itself). < 0 where a pair has no
// depth to measure (two open sheets). FCL's deepest triangle pair is no
// depth: two faces lying on one another (an aligner standing on a block)
// gave 108 mm.
double RigidDepth(const std::vector<Shell>& robot_shells, const Eigen::Isometry3d& pose,
                  const TriangleMesh& part_mesh) {
  const std::vector<Shell> part_shells = SplitIntoShells(part_mesh);
  Aabb robot_box;
  for (const Shell& r : robot_shells) robot_box.Extend(r.box);
  SurfaceDepthOptions options;
  options.resolution = 1e-4 * robot_box.Diagonal();
  options.coarse_above = 1e-2 * robot_box.Diagonal();  // deeper: to 1/16 (a plate through a plate: minutes else)
  double depth = 0;
  std::vector<std::unique_ptr<DepthSurface>> part_surfaces(part_shells.size());  // built where a pair needs one
  for (const Shell& r : robot_shells) {
    const Aabb placed = r.box.Transformed(pose);  // about the shell, turned with D
    std::unique_ptr<DepthSurface> robot_surface;
    for (std::size_t i = 0; i < part_shells.size(); ++i) {
      const Shell& p = part_shells[i];
      if (placed.SeparatedFrom(p.box)) continue;
      if (r.convex && p.convex) {
        depth = std::max(depth, ConvexSignedDepth(r, pose, p));
        continue;
      }
      if (!robot_surface) robot_surface = std::make_unique<DepthSurface>(r);
      if (!part_surfaces[i]) part_surfaces[i] = std::make_unique<DepthSurface>(p);
      const DepthSurface& part_surface = *part_surfaces[i];
      if (!robot_surface->solid() && !part_surface.solid()) return -1;
      depth = std::max(depth, MeasureSurfaceDepth(*robot_surface, pose, part_surface, options).upper);
    }
  }
  return depth;
}

// `measured`: the triangles of `part_mesh` that FCL is given (all of them,
// or those near D: CropMesh).
PartContact Measure(const FclModel& robot, const std::vector<Shell>& robot_shells, const fcl::Transform3d& tf,
                    const TriangleMesh& measured, const TriangleMesh& part_mesh) {
  PartContact contact;
  const std::shared_ptr<FclModel> part = BuildFclModel(measured);
  fcl::CollisionRequestd request(1000, true);  // every crossing pair (up to 1000), with depths
  fcl::CollisionResultd result;
  fcl::collide(&robot, tf, part.get(), fcl::Transform3d::Identity(), request, result);
  if (result.isCollision()) {
    contact.intersects = true;
    contact.depth = 0;
    for (std::size_t i = 0; i < result.numContacts(); ++i) {
      const fcl::Contactd& c = result.getContact(i);
      if (i == 0 || c.penetration_depth > contact.depth) {
        contact.depth = std::max(0.0, c.penetration_depth);
        contact.point = c.pos;
      }
    }
    const double exact = RigidDepth(robot_shells, tf, part_mesh);
    if (exact >= 0) {
      contact.depth = exact;
      contact.depth_exact = true;
    }
    return contact;
  }
  fcl::DistanceRequestd distance_request(true);  // with the nearest points (world frame in FCL >= 0.6)
  fcl::DistanceResultd distance_result;
  fcl::distance(&robot, tf, part.get(), fcl::Transform3d::Identity(), distance_request, distance_result);
  contact.distance = std::max(0.0, distance_result.min_distance);
  contact.point = distance_result.nearest_points[1];
  return contact;
}

}  // namespace

std::vector<PartContact> MeasurePartContacts(const TriangleMesh& robot, const Pose& pose,
                                             const TriangleMesh& environment, const std::vector<int>& part_of_triangle,
                                             const std::vector<std::string>& names, double reach, int max_parts) {
  std::vector<PartContact> all;
  if (robot.triangles.empty() || environment.triangles.empty()) return all;
  const std::shared_ptr<FclModel> robot_model = BuildFclModel(robot);
  fcl::Transform3d tf = fcl::Transform3d::Identity();
  tf.linear() = pose.q.toRotationMatrix();
  tf.translation() = pose.t;
  const std::vector<TriangleMesh> parts = SplitParts(environment, part_of_triangle);
  const std::vector<Shell> robot_shells = SplitIntoShells(robot);
  // D's box grown by the reach: a triangle whose box misses it lies farther
  // than `reach` from D.
  Aabb near_box;
  for (const Eigen::Vector3d& v : robot.vertices) near_box.Extend(pose.q * v + pose.t);
  near_box.min.array() -= reach;
  near_box.max.array() += reach;
  for (std::size_t p = 0; p < parts.size(); ++p) {
    if (parts[p].triangles.empty()) continue;
    // A car body of a million triangles would cost seconds and most of a
    // gigabyte as one FCL model: its triangles near D give the same answer.
    // Far triangles (box distance > reach) can neither cross D nor come
    // within reach, so a part that crosses D or lies within reach is
    // measured exactly from its near triangles; any other part, which only
    // counts as the nearest where none is within reach, from all of them.
    // (The depth where shells are convex is always taken over the whole
    // part: its shells are split from it.)
    const TriangleMesh near = CropMesh(parts[p], near_box);
    PartContact contact;
    if (near.triangles.size() < parts[p].triangles.size() && !near.triangles.empty()) {
      contact = Measure(*robot_model, robot_shells, tf, near, parts[p]);
      if (!contact.intersects && contact.distance > reach)
        contact = Measure(*robot_model, robot_shells, tf, parts[p], parts[p]);
    } else {
      contact = Measure(*robot_model, robot_shells, tf, parts[p], parts[p]);
    }
    contact.part = static_cast<int>(p);
    contact.name = p < names.size() ? names[p] : "part " + std::to_string(p);
    all.push_back(contact);
  }
  // Deepest intersection first, then nearest; ties by part index (deterministic).
  std::sort(all.begin(), all.end(), [](const PartContact& a, const PartContact& b) {
    if (a.intersects != b.intersects) return a.intersects;
    if (a.intersects && a.depth != b.depth) return a.depth > b.depth;
    if (!a.intersects && a.distance != b.distance) return a.distance < b.distance;
    return a.part < b.part;
  });
  std::vector<PartContact> kept;
  for (const PartContact& c : all) {
    if (static_cast<int>(kept.size()) >= max_parts) break;
    if (c.intersects || c.distance <= reach || kept.empty()) kept.push_back(c);
  }
  return kept;
}

std::string DescribePartContact(const PartContact& c) {
  const char* frees = c.frees ? "; without it D comes out" : "";
  if (c.intersects) {
    return Fmt("%s (intersects, depth %.4g%s at [%.6g, %.6g, %.6g]%s)", c.name.c_str(), c.depth,
               c.depth_exact ? "" : " (local estimate)", c.point.x(), c.point.y(), c.point.z(), frees);
  }
  return Fmt("%s (%.4g away, closest at [%.6g, %.6g, %.6g]%s)", c.name.c_str(), c.distance, c.point.x(), c.point.y(),
             c.point.z(), frees);
}

}  // namespace ausbau
