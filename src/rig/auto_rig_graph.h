// The automatic rig's phases (rig/auto_rig.h), each over one shared picture of the drawing's
// parts: what they are and where they overlap (auto_rig_parts.cpp), the body, the tree and
// each part's kind (auto_rig_tree.cpp), hinges and sewing (auto_rig_joints.cpp), handles and
// strands (auto_rig.cpp). Internal to the rig library.
#pragma once

#include "frame/joints.h"
#include "rig/auto_rig.h"
#include "rig/part_names.h"

#include <set>
#include <string>
#include <vector>

namespace mar {

/// A closed, filled sub-shape as the rig sees it.
struct PartGeo {
  int shape = -1;
  Points ring;  ///< the outer outline (the largest closed contour, or the outline of its pieces)
  double area = 0;
  Vec2 lo{0, 0}, hi{0, 0};
  Vec2 centroid{0, 0};
  std::vector<std::string> words;
  bool named = false;
  Hint hint = Hint::None;
};

/// The parts and what the phases found about them; indices are into `geo` (the parts), never
/// into the character's shapes unless said.
struct PartGraph {
  PartGraph(const Character& c, double h) : ch(c), height(h) {}
  const Character& ch;
  double height;                 ///< the drawing's height (at least 1e-9)
  std::set<int> members;         ///< shapes in swap sets and triggers: not parts of the tree
  std::vector<PartGeo> geo;
  size_t n = 0;                  ///< geo.size()
  size_t left_small = 0;         ///< filled shapes past the most parts there may be (the smallest)
  std::vector<std::vector<double>> overlap;    ///< area both parts cover
  std::vector<std::vector<Vec2>> overlap_at;   ///< where they overlap (or touch, or a connector ends)
  std::vector<char> scenery;                   ///< left out: a backdrop, a ground shadow
  std::vector<int> container;                  ///< the part a detail or twin rides on, else -1
  std::vector<int> group_part;                 ///< a piece of a group drawn as one part: that part (its largest piece), else -1
  std::vector<std::vector<int>> nb;            ///< neighbours: overlapping, touching or joined by a stroke
  std::vector<char> is_part;                   ///< per character shape
  std::vector<std::vector<int>> via;           ///< the connector stroke's shape between two parts, else -1
  std::vector<std::vector<Vec2>> stroke_end;   ///< a connector's end at the first part
  size_t root = 0;                             ///< the body
  std::vector<int> parent;                     ///< in the tree (a detail: its container)
  std::vector<Axis> axes;                      ///< each part's principal axis
  std::vector<char> flap;                      ///< a limb by its name, attached along a side
  std::vector<char> end_attached;              ///< a limb hung along its parent's side, attached at one end
  std::vector<Vec2> attach_at;                 ///< ...at this point

  /// The part at a point: inside it or within 2% of the height of it, the smallest holding
  /// it; parts mostly inside another only `with_details`. -1: none.
  int part_at(const Vec2& q, bool with_details) const;
  const std::string& id(size_t part) const { return ch.shapes[size_t(geo[part].shape)].id; }
};

// auto_rig_parts.cpp
/// The closed, filled sub-shapes that are not swap or trigger members.
void find_parts(PartGraph& g, const AutoRigOptions& options);
/// Groups whose pieces make one region become one part (part of find_parts; G.group_part).
void join_groups(PartGraph& g);
/// Overlaps, scenery (into out.left_out), details and twins, neighbours and connectors.
void relate_parts(PartGraph& g, AutoRig& out);

// auto_rig_tree.cpp
/// The body, the tree out from it, and each part's kind (out.parts, one per part).
void grow_tree(PartGraph& g, AutoRig& out);

// auto_rig_joints.cpp
/// A hinge at each limb's drawn joint (and the head's neck), into out.rig.joints.
void place_hinges(const PartGraph& g, AutoRig& out, const AutoRigOptions& options);
/// Sewing edits that make the solver's sewing follow the tree (out.rig.sewing).
void sew_tree(const PartGraph& g, AutoRig& out);

}  // namespace mar
