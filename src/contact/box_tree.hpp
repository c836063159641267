// A tree of axis-aligned bounding boxes over a set of boxes (the triangles of self-contact's
// surfaces and of surface obstacles, docs/contact.md): built in O(n log n), each node split at the
// median of its boxes' centres along their spread's longest side; a query visits every box that
// overlaps a given one in O(log n + hits). The split breaks ties by index, so every rank builds the
// same tree from the same boxes. Pure.
#pragma once

#include <Eigen/Geometry>
#include <vector>

namespace hs {

class BoxTree {
 public:
  explicit BoxTree(std::vector<Eigen::AlignedBox3d> boxes);

  // visit(i) for every box i that overlaps `box` (touching counts).
  template <class Visit>
  void overlapping(const Eigen::AlignedBox3d& box, Visit&& visit) const {
    if (nodes_.empty()) return;
    std::vector<int> stack{0};
    while (!stack.empty()) {
      const Node& node = nodes_[stack.back()];
      const int here = stack.back();
      stack.pop_back();
      if (!node.box.intersects(box)) continue;
      if (node.right < 0) {
        for (int k = node.first; k < node.first + node.count; ++k)
          if (boxes_[order_[k]].intersects(box)) visit(order_[k]);
        continue;
      }
      stack.push_back(here + 1);
      stack.push_back(node.right);
    }
  }

  // A nearest-item search from x: visit(i) for the boxes that may hold an item nearer than
  // `best` (a squared distance the visitor lowers as it finds nearer items), the nearer child
  // first so that it prunes the other.
  template <class Visit>
  void nearest(const Eigen::Vector3d& x, const double& best, Visit&& visit) const {
    if (nodes_.empty()) return;
    std::vector<int> stack{0};
    while (!stack.empty()) {
      const int here = stack.back();
      const Node& node = nodes_[here];
      stack.pop_back();
      if (node.box.squaredExteriorDistance(x) >= best) continue;
      if (node.right < 0) {
        for (int k = node.first; k < node.first + node.count; ++k) visit(order_[k]);
        continue;
      }
      const bool left_nearer = nodes_[here + 1].box.squaredExteriorDistance(x) <=
                               nodes_[node.right].box.squaredExteriorDistance(x);
      stack.push_back(left_nearer ? node.right : here + 1);
      stack.push_back(left_nearer ? here + 1 : node.right);
    }
  }

 private:
  struct Node {
    Eigen::AlignedBox3d box;
    int first = 0, count = 0;  // a leaf's boxes: order_[first, first + count)
    int right = -1;            // an inner node's second child (its first is the next node)
  };
  int build(int first, int count);

  std::vector<Eigen::AlignedBox3d> boxes_;
  std::vector<Node> nodes_;
  std::vector<int> order_;
};

}  // namespace hs
