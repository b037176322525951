// Dynamic AABB tree (the broad phase's index): insertion by branch-and-bound search for the
// sibling of least surface-area-heuristic cost, AVL-style rotations on the way back up.
//
// Invariants: every internal node has two children, its box encloses both and its height is one
// more than the taller child's; a leaf has height 0; a free node has height -1 and is on the free
// list exactly once. The SAH cost of making node S the sibling of a new leaf L is the perimeter of
// the new parent, union(S, L), plus the perimeter every ancestor of S grows by; ancestors' growth
// is the "inherited" cost, and perimeter(L) plus the inherited cost bounds every sibling below a
// node (Bittner, Hapala, Havran, "Fast Insertion-Based Optimization of Bounding Volume
// Hierarchies", 2013). The search is greedy, one path from the root: it stops where pairing with
// the node costs no more than the bound of either child, else follows the cheaper child. A full
// branch-and-bound search found slightly better siblings but visited most of the tree when many
// fat boxes overlap (3000 boxes falling in step: a third of the engine's instructions). Ties go
// to the first child, so the same operations build the same tree. rebuild() replaces all internal
// nodes at once, for steps in which most leaves move, and refit_or_rebuild() first tries only
// refitting their boxes: the broad phase sorts the pairs it finds, so no result depends on the
// tree's shape.
#include "collision/aabb_tree.h"


#include <algorithm>
#include <cassert>
#include <limits>

namespace fx2d::detail {

int AabbTree::allocate_node() {
  if (free_list_ == null_node) {
    nodes_.push_back(Node{});
    return int(nodes_.size()) - 1;
  }
  const int id = free_list_;
  free_list_ = nodes_[id].parent_or_next;
  nodes_[id] = Node{};
  return id;
}

void AabbTree::free_node(int id) {
  nodes_[id].parent_or_next = free_list_;
  nodes_[id].height = -1;
  free_list_ = id;
}

void AabbTree::reserve(int proxies) {
  nodes_.reserve(static_cast<std::size_t>(2 * proxies));
  leaves_.reserve(static_cast<std::size_t>(proxies));
}

int AabbTree::create_proxy(const FxAABB& fat_box) {
  const int leaf = allocate_node();
  nodes_[leaf].box = fat_box;
  insert_leaf(leaf);
  ++proxy_count_;
  return leaf;
}

void AabbTree::destroy_proxy(int proxy) {
  assert(nodes_[proxy].is_leaf() && nodes_[proxy].height == 0);
  remove_leaf(proxy);
  free_node(proxy);
  --proxy_count_;
}

void AabbTree::move_proxy(int proxy, const FxAABB& fat_box) {
  assert(nodes_[proxy].is_leaf() && nodes_[proxy].height == 0);
  const int parent = nodes_[proxy].parent_or_next;
  nodes_[proxy].box = fat_box;
  // A box its parent still encloses keeps the leaf where it is: every ancestor encloses it too.
  // The parent's box may then be looser than its children's union until a refit or rebuild.
  if (parent != null_node && nodes_[parent].box.contains(fat_box)) return;
  remove_leaf(proxy);
  insert_leaf(proxy);
}

void AabbTree::set_fat_box(int proxy, const FxAABB& fat_box) {
  assert(nodes_[proxy].is_leaf() && nodes_[proxy].height == 0);
  nodes_[proxy].box = fat_box;
}

void AabbTree::rebuild() {
  leaves_.clear();
  for (int id = 0; id < int(nodes_.size()); ++id) {
    if (nodes_[id].height == 0) {
      // The doubled centre (exact, and enough to compare and to measure extents), read once
      // here rather than from the scattered nodes at every comparison of every level.
      leaves_.push_back({nodes_[id].box.lower + nodes_[id].box.upper, id});
    } else if (nodes_[id].height > 0) {
      free_node(id);
    }
  }
  root_ = leaves_.empty() ? null_node : build_subtree(0, int(leaves_.size()));
  if (root_ != null_node) nodes_[root_].parent_or_next = null_node;
  built_area_ratio_ = area_ratio();
}

void AabbTree::refit_or_rebuild(float allowed_growth) {
  if (root_ == null_node || nodes_[root_].is_leaf()) return;
  const float internal_perimeters = refit_subtree(root_);
  if (internal_perimeters > allowed_growth * built_area_ratio_ * nodes_[root_].box.perimeter()) rebuild();
}

// Recomputes the boxes of the internal nodes below and at `id`, children first, and returns the
// sum of their perimeters. The recursion is as deep as the tree, which rotations keep shallow.
float AabbTree::refit_subtree(int id) {
  Node& node = nodes_[id];
  if (node.is_leaf()) return 0.0f;
  const float below = refit_subtree(node.child1) + refit_subtree(node.child2);
  node.box = union_of(nodes_[node.child1].box, nodes_[node.child2].box);
  return below + node.box.perimeter();
}

namespace {

// The doubled centre along one axis; NaN sorts last so that the order stays total.
float centre_key(FxVec2f doubled_centre, bool along_x) {
  const float key = along_x ? doubled_centre.x : doubled_centre.y;
  return key == key ? key : std::numeric_limits<float>::infinity();
}

}  // namespace

// The subtree over leaves_[first, last): halves of equal size (within one), so it is balanced.
// Leaves are ordered by centre, then by id, a total order: each half is the same set whatever
// order the leaves arrived in, so the same boxes build the same tree.
int AabbTree::build_subtree(int first, int last) {
  if (last - first == 1) return leaves_[first].id;
  FxVec2f lowest{std::numeric_limits<float>::max(), std::numeric_limits<float>::max()};
  FxVec2f highest = -lowest;
  for (int i = first; i < last; ++i) {
    lowest = min(lowest, leaves_[i].doubled_centre);
    highest = max(highest, leaves_[i].doubled_centre);
  }
  const bool along_x = highest.x - lowest.x >= highest.y - lowest.y;
  const int middle = first + (last - first) / 2;
  std::nth_element(leaves_.begin() + first, leaves_.begin() + middle, leaves_.begin() + last,
                   [along_x](const LeafCentre& a, const LeafCentre& b) {
                     const float key_a = centre_key(a.doubled_centre, along_x);
                     const float key_b = centre_key(b.doubled_centre, along_x);
                     return key_a < key_b || (key_a == key_b && a.id < b.id);
                   });
  const int child1 = build_subtree(first, middle);
  const int child2 = build_subtree(middle, last);
  const int parent = allocate_node();
  Node& node = nodes_[parent];
  node.child1 = child1;
  node.child2 = child2;
  node.box = union_of(nodes_[child1].box, nodes_[child2].box);
  node.height = 1 + std::max(nodes_[child1].height, nodes_[child2].height);
  nodes_[child1].parent_or_next = parent;
  nodes_[child2].parent_or_next = parent;
  return parent;
}

int AabbTree::find_best_sibling(const FxAABB& box) const {
  const float leaf_perimeter = box.perimeter();
  int node_id = root_;
  float inherited_cost = 0.0f;
  // Invariant: inherited_cost is how much every ancestor of node_id grows when the leaf joins below it.
  while (!nodes_[node_id].is_leaf()) {
    const Node& node = nodes_[node_id];
    const float parent_perimeter = union_of(node.box, box).perimeter();
    const float here = parent_perimeter + inherited_cost;
    const float child_inherited = inherited_cost + parent_perimeter - node.box.perimeter();
    // A leaf child's cost is exact; an internal child's is the least any sibling below it can cost.
    const auto descent_cost = [&](int child) {
      const Node& c = nodes_[child];
      const float joined = union_of(c.box, box).perimeter();
      return c.is_leaf() ? joined + child_inherited : leaf_perimeter + joined - c.box.perimeter() + child_inherited;
    };
    const float cost1 = descent_cost(node.child1);
    const float cost2 = descent_cost(node.child2);
    if (here <= cost1 && here <= cost2) break;
    node_id = cost1 <= cost2 ? node.child1 : node.child2;
    inherited_cost = child_inherited;
  }
  return node_id;
}

void AabbTree::insert_leaf(int leaf) {
  if (root_ == null_node) {
    root_ = leaf;
    nodes_[leaf].parent_or_next = null_node;
    return;
  }
  const FxAABB box = nodes_[leaf].box;
  const int sibling = find_best_sibling(box);
  const int old_parent = nodes_[sibling].parent_or_next;
  const int new_parent = allocate_node();
  Node& parent = nodes_[new_parent];
  parent.parent_or_next = old_parent;
  parent.box = union_of(box, nodes_[sibling].box);
  parent.child1 = sibling;
  parent.child2 = leaf;
  parent.height = nodes_[sibling].height + 1;
  nodes_[sibling].parent_or_next = new_parent;
  nodes_[leaf].parent_or_next = new_parent;
  if (old_parent == null_node) {
    root_ = new_parent;
  } else if (nodes_[old_parent].child1 == sibling) {
    nodes_[old_parent].child1 = new_parent;
  } else {
    nodes_[old_parent].child2 = new_parent;
  }
  refit_upwards(old_parent);
}

void AabbTree::remove_leaf(int leaf) {
  if (leaf == root_) {
    root_ = null_node;
    return;
  }
  const int parent = nodes_[leaf].parent_or_next;
  const int grandparent = nodes_[parent].parent_or_next;
  const int sibling = nodes_[parent].child1 == leaf ? nodes_[parent].child2 : nodes_[parent].child1;
  free_node(parent);
  nodes_[sibling].parent_or_next = grandparent;
  if (grandparent == null_node) {
    root_ = sibling;
    return;
  }
  if (nodes_[grandparent].child1 == parent) {
    nodes_[grandparent].child1 = sibling;
  } else {
    nodes_[grandparent].child2 = sibling;
  }
  refit_upwards(grandparent);
}

// Restores balance, height and box of `id` and of each of its ancestors. It stops at the first
// node that keeps its place, height and box: every ancestor above still encloses it and keeps
// its children's heights. A leaf moving within its neighbourhood changes only a few levels, not
// the path to the root.
void AabbTree::refit_upwards(int id) {
  while (id != null_node) {
    const int top = balance(id);
    Node& node = nodes_[top];
    const int height = 1 + std::max(nodes_[node.child1].height, nodes_[node.child2].height);
    const FxAABB box = union_of(nodes_[node.child1].box, nodes_[node.child2].box);
    const bool unchanged = top == id && height == node.height && box.lower == node.box.lower && box.upper == node.box.upper;
    node.height = height;
    node.box = box;
    if (unchanged) return;
    id = node.parent_or_next;
  }
}

// If one child of `id` is more than one level taller than the other, lifts that child into
// id's place and returns it; otherwise returns id. Children's heights and boxes must be current.
int AabbTree::balance(int id) {
  const Node& node = nodes_[id];
  if (node.is_leaf()) return id;
  const int difference = nodes_[node.child2].height - nodes_[node.child1].height;
  if (difference > 1) return rotate_up(id, node.child2);
  if (difference < -1) return rotate_up(id, node.child1);
  return id;
}

// Rotation: `tall` (a child of `top`) takes top's place. Of tall's two children, the taller stays
// with tall and the shorter goes to top in tall's old slot, which shortens the subtree by one.
int AabbTree::rotate_up(int top, int tall) {
  Node& upper = nodes_[top];
  Node& lifted = nodes_[tall];
  const bool kept_first = nodes_[lifted.child1].height >= nodes_[lifted.child2].height;
  const int kept = kept_first ? lifted.child1 : lifted.child2;
  const int moved = kept_first ? lifted.child2 : lifted.child1;

  lifted.parent_or_next = upper.parent_or_next;
  upper.parent_or_next = tall;
  if (lifted.parent_or_next == null_node) {
    root_ = tall;
  } else if (nodes_[lifted.parent_or_next].child1 == top) {
    nodes_[lifted.parent_or_next].child1 = tall;
  } else {
    nodes_[lifted.parent_or_next].child2 = tall;
  }

  if (upper.child1 == tall) {
    upper.child1 = moved;
  } else {
    upper.child2 = moved;
  }
  nodes_[moved].parent_or_next = top;
  upper.box = union_of(nodes_[upper.child1].box, nodes_[upper.child2].box);
  upper.height = 1 + std::max(nodes_[upper.child1].height, nodes_[upper.child2].height);

  lifted.child1 = top;
  lifted.child2 = kept;
  return tall;
}

int AabbTree::height() const { return root_ == null_node ? 0 : nodes_[root_].height; }

float AabbTree::area_ratio() const {
  if (root_ == null_node || nodes_[root_].is_leaf()) return 0.0f;
  float internal_perimeters = 0.0f;
  for (const Node& node : nodes_) {
    if (node.height > 0) internal_perimeters += node.box.perimeter();
  }
  return internal_perimeters / nodes_[root_].box.perimeter();
}

bool AabbTree::validate() const {
  const int node_count = int(nodes_.size());
  int free_count = 0;
  for (int id = free_list_; id != null_node; id = nodes_[id].parent_or_next) {
    if (id < 0 || id >= node_count || nodes_[id].height != -1 || ++free_count > node_count) return false;
  }

  int reachable = 0;
  int leaves = 0;
  if (root_ != null_node) {
    if (nodes_[root_].parent_or_next != null_node) return false;
    std::vector<int> pending{root_};
    while (!pending.empty()) {
      const int id = pending.back();
      pending.pop_back();
      if (id < 0 || id >= node_count || ++reachable > node_count) return false;
      const Node& node = nodes_[id];
      if (node.is_leaf()) {
        if (node.child2 != null_node || node.height != 0) return false;
        ++leaves;
        continue;
      }
      for (const int child : {node.child1, node.child2}) {
        if (child < 0 || child >= node_count || nodes_[child].parent_or_next != id) return false;
        if (!node.box.contains(nodes_[child].box)) return false;
        pending.push_back(child);
      }
      if (node.height != 1 + std::max(nodes_[node.child1].height, nodes_[node.child2].height)) return false;
    }
  }
  return leaves == proxy_count_ && reachable + free_count == node_count;
}

}  // namespace fx2d::detail
