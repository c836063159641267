// A closed triangle surface as a rigid obstacle (docs/contact.md, "Surface obstacles"): its
// signed distance from the closest point, found through a tree of bounding boxes built once
// (O(log n) a query), signed by the angle-weighted pseudo-normal of the closest point's face,
// edge or vertex, which is exact for any closed, consistently oriented surface. Pure.
#pragma once

#include <Eigen/Dense>
#include <array>
#include <memory>
#include <vector>

#include "contact/box_tree.hpp"
#include "contact/obstacle.hpp"

namespace hs {

class TriangleSurface {
 public:
  // A closed surface, each edge shared by two triangles in opposite directions, its
  // triangles counter-clockwise seen from outside, none of zero area (read_obstacle_surface
  // checks all of that in a file; here it is assumed).
  TriangleSurface(std::vector<Eigen::Vector3d> vertices, std::vector<std::array<int, 3>> triangles);

  // d > 0 outside; its gradient and Hessian: zero Hessian where the closest point is inside
  // a face, (P - g g^T) / d beside an edge (P the projector normal to it) or a vertex (P = I).
  SignedDistance distance(const Eigen::Vector3d& x) const;

  size_t num_triangles() const { return triangles_.size(); }
  const std::vector<Eigen::Vector3d>& vertices() const { return vertices_; }
  const std::vector<std::array<int, 3>>& triangles() const { return triangles_; }

 private:
  std::vector<Eigen::Vector3d> vertices_;
  std::vector<std::array<int, 3>> triangles_;
  std::vector<Eigen::Vector3d> face_normal_, vertex_normal_, edge_normal_;  // edge: 3 a triangle
  // An edge between coplanar faces, a vertex amid them (a tessellated flat side): the
  // distance is the plane's there, flat, not curved round the feature.
  std::vector<char> flat_edge_, flat_vertex_;
  std::unique_ptr<BoxTree> tree_;  // over the triangles' boxes
};

}  // namespace hs
