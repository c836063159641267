#include "contact/box_tree.hpp"

#include <algorithm>
#include <numeric>

namespace hs {

BoxTree::BoxTree(std::vector<Eigen::AlignedBox3d> boxes) : boxes_(std::move(boxes)) {
  order_.resize(boxes_.size());
  std::iota(order_.begin(), order_.end(), 0);
  nodes_.reserve(2 * boxes_.size());
  if (!boxes_.empty()) build(0, static_cast<int>(boxes_.size()));
}

int BoxTree::build(int first, int count) {
  const int index = static_cast<int>(nodes_.size());
  nodes_.emplace_back();
  Eigen::AlignedBox3d box, centres;
  for (int k = first; k < first + count; ++k) {
    box.extend(boxes_[order_[k]]);
    centres.extend(boxes_[order_[k]].center());
  }
  nodes_[index].box = box;
  constexpr int kLeafSize = 4;
  if (count <= kLeafSize) {
    nodes_[index].first = first;
    nodes_[index].count = count;
    return index;
  }
  int axis = 0;
  centres.sizes().maxCoeff(&axis);
  const int half = count / 2;
  std::nth_element(order_.begin() + first, order_.begin() + first + half,
                   order_.begin() + first + count, [&](int s, int t) {
                     const double cs = boxes_[s].center()(axis), ct = boxes_[t].center()(axis);
                     return cs < ct || (cs == ct && s < t);
                   });
  build(first, half);
  const int right = build(first + half, count - half);
  nodes_[index].right = right;
  return index;
}

}  // namespace hs
