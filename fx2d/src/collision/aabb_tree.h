// Dynamic AABB tree: the broad phase's spatial index.
//
// Leaves hold enlarged ("fat") boxes, so a proxy whose tight box still fits inside its fat box
// need not move in the tree. Insertion descends greedily towards the sibling of least
// surface-area-heuristic cost (the perimeter increase over the whole path, in 2D), and the tree
// is kept shallow by rotations on the way back up. Nodes live in one array with a free list and are addressed by
// index; after warm-up no operation allocates. All choices are made in a fixed order, so the same
// sequence of operations builds the same tree.
#pragma once

#include <cstdint>
#include <vector>

#include "fx2d/Math.h"

namespace fx2d::detail {

class AabbTree {
 public:
  static constexpr int null_node = -1;

  // Grows storage for this many proxies, so that later operations up to that size do not allocate.
  void reserve(int proxies);
  // Adds a leaf holding `fat_box` and returns its proxy id (a node index, stable until destroyed).
  int create_proxy(const FxAABB& fat_box);
  void destroy_proxy(int proxy);
  // Replaces the proxy's fat box: the leaf is removed and reinserted, unless its parent's box
  // still encloses the new one.
  void move_proxy(int proxy, const FxAABB& fat_box);
  // For many proxies at once: replace each one's fat box with set_fat_box(), which leaves the
  // internal boxes stale, then rebuild() the internal nodes from all leaves, top down, each node
  // splitting its leaves at the median centre along the longer extent. When most proxies move in
  // one step (a scene falling in unison) that costs less than moving them one by one. Proxy ids
  // stay valid; no query or edit may come between the two.
  void set_fat_box(int proxy, const FxAABB& fat_box);
  void rebuild();
  // In place of rebuild(), after set_fat_box(): first only refits the internal boxes over the
  // present shape, one pass over the nodes, and rebuilds only when the refitted tree's
  // area_ratio() grew past `allowed_growth` times the one it had when last rebuilt. Bodies
  // falling together keep their neighbours, and the tree built for them stays good.
  void refit_or_rebuild(float allowed_growth);

  const FxAABB& fat_box(int proxy) const { return nodes_[proxy].box; }

  // Calls visit(proxy) for every leaf whose fat box overlaps `box`, in a deterministic order;
  // visit returns false to stop early. Holds its stack on the caller's stack, not in the tree, so
  // any number of threads query one tree at once.
  template <class Visit>
  void query(const FxAABB& box, Visit&& visit) const {
    if (root_ == null_node) return;
    // Depth first, a walk holds at most one waiting sibling per level above the node it opens:
    // fewer than height + 1 entries.
    const int deepest = nodes_[root_].height + 1;
    if (deepest <= local_stack_size) {
      int stack[local_stack_size];
      walk(box, stack, visit);
    } else {
      std::vector<int> stack(static_cast<std::size_t>(deepest));  // rotations keep real trees far shallower
      walk(box, stack.data(), visit);
    }
  }

  // Calls visit(proxy, other) once for every two leaves whose fat boxes overlap: one walk of the
  // tree against itself, which opens each pair of overlapping nodes once, where a query per leaf
  // opens the path to every overlap from the root, and twice over. In a fixed order.
  template <class Visit>
  void for_each_overlapping_pair(Visit&& visit) const {
    if (root_ == null_node) return;
    // Each node pair opened leaves at most three waiting, and the walk goes at most twice the height deep.
    const int deepest = 6 * (nodes_[root_].height + 1);
    if (deepest <= local_pair_stack_size) {
      NodePair stack[local_pair_stack_size];
      walk_pairs(stack, visit);
    } else {
      std::vector<NodePair> stack(static_cast<std::size_t>(deepest));
      walk_pairs(stack.data(), visit);
    }
  }

  int height() const;           // 0 for an empty tree or a single leaf
  int proxy_count() const { return proxy_count_; }
  // Sum of internal nodes' perimeters divided by the root's: the quality measure SAH minimises.
  float area_ratio() const;
  // Checks the structural invariants (parents, heights, boxes enclosing children, free list) and
  // returns false on the first violation. For tests.
  bool validate() const;

 private:
  // 32 bytes, aligned to them: a node never straddles two cache lines, and a walk reads a box
  // and the links beside it with one line.
  struct alignas(32) Node {
    FxAABB box;
    int parent_or_next = null_node;  // parent while in the tree, next free node while free
    int child1 = null_node;
    int child2 = null_node;
    int height = 0;                  // leaf 0, free -1
    bool is_leaf() const { return child1 == null_node; }
  };

  int allocate_node();
  void free_node(int id);
  int find_best_sibling(const FxAABB& box) const;
  void insert_leaf(int leaf);
  void remove_leaf(int leaf);
  void refit_upwards(int id);
  int balance(int id);
  int rotate_up(int top, int tall);
  int build_subtree(int first, int last);
  float refit_subtree(int id);

  static constexpr int local_stack_size = 128;
  // A child's box is tested as its parent opens: a child that misses costs no trip through the
  // stack, and of two that overlap the walk goes straight on into the second and pushes only the
  // first, the order a stack of both would pop them in (the order stays what it was). The box is
  // taken by value: a reference made the compiler reload it for every test, since the visitor's
  // stores might have changed it. The walk runs some 37 instructions a node, predicted well: on
  // settling_boxes 3000's pair search (29 nodes a query, 68M cycles in 200 steps) pushing both
  // children without a branch took 1.17 times as long, a four-lane box test 1.16, and
  // prefetching the grandchildren 1.02. A query from a moved body costs some 750-790 time-stamp
  // cycles for about 1,000 instructions on settling_boxes 800 and 3000 alike (an rdtsc probe over
  // 200 steps, sleeping off): 1.3 instructions a cycle, where the contact passes run about 5. The
  // queries take most of the pair search (5.4M of its 7.2M cycles on 800, 32.9M of 50.0M on 3000),
  // the walks of the tree against itself the rest. A node opened reads three lines, its own and its
  // two children's. Each internal node's children's boxes and ids copied into one 64-byte line by
  // the refit or rebuild, and walked while no change followed, did not pay (`ab`, sleeping off): in
  // the steps that refit, mean step 1.001 on settling_boxes 800 and 1.008 on 3000; refitting in
  // every step that moves a body, so that every query walks the copies, 0.988 on settling_boxes 800
  // and 0.978 on pile 800, with pile's median broad phase 1.148 and 2.6% and 1.0% more instructions.
  template <class Visit>
  void walk(FxAABB box, int* stack, Visit& visit) const {
    if (!overlaps(nodes_[root_].box, box)) return;
    int size = 0;
    int id = root_;
    for (;;) {
      const Node& node = nodes_[id];
      if (node.is_leaf()) {
        if (!visit(id) || size == 0) return;
        id = stack[--size];
        continue;
      }
      const bool first_overlaps = overlaps(nodes_[node.child1].box, box);
      if (overlaps(nodes_[node.child2].box, box)) {
        if (first_overlaps) stack[size++] = node.child1;
        id = node.child2;
      } else if (first_overlaps) {
        id = node.child1;
      } else if (size > 0) {
        id = stack[--size];
      } else {
        return;
      }
    }
  }

  struct NodePair {
    int a, b;
  };
  static constexpr int local_pair_stack_size = 256;

  // A node paired with itself stands for every pair of leaves below it; two nodes, for every leaf
  // of one with every leaf of the other, opened on the side with the larger box.
  template <class Visit>
  void walk_pairs(NodePair* stack, Visit& visit) const {
    int size = 0;
    stack[size++] = {root_, root_};
    while (size > 0) {
      const NodePair pair = stack[--size];
      const Node& a = nodes_[pair.a];
      if (pair.a == pair.b) {
        if (a.is_leaf()) continue;
        stack[size++] = {a.child2, a.child2};
        stack[size++] = {a.child1, a.child1};
        if (overlaps(nodes_[a.child1].box, nodes_[a.child2].box)) stack[size++] = {a.child1, a.child2};
        continue;
      }
      const Node& b = nodes_[pair.b];
      if (a.is_leaf() && b.is_leaf()) {
        visit(pair.a, pair.b);
        continue;
      }
      const bool open_a = b.is_leaf() || (!a.is_leaf() && a.box.perimeter() >= b.box.perimeter());
      const Node& opened = open_a ? a : b;
      const int kept = open_a ? pair.b : pair.a;
      const FxAABB& kept_box = open_a ? b.box : a.box;
      if (overlaps(nodes_[opened.child2].box, kept_box)) stack[size++] = {opened.child2, kept};
      if (overlaps(nodes_[opened.child1].box, kept_box)) stack[size++] = {opened.child1, kept};
    }
  }

  std::vector<Node> nodes_;
  int root_ = null_node;
  int free_list_ = null_node;
  int proxy_count_ = 0;
  float built_area_ratio_ = 0.0f;  // area_ratio() just after the last rebuild()
  struct LeafCentre {
    FxVec2f doubled_centre;  // lower + upper of the leaf's box
    int id;
  };
  std::vector<LeafCentre> leaves_;  // rebuild()'s scratch
};

}  // namespace fx2d::detail
