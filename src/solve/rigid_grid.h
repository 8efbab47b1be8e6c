// The topology-aware rigid grid (seed 003; docs/algorithms.md §4).
//
// Representation. The character's filled region gets a regular grid trimmed to the cells wholly
// inside it (the interior grid; cell = the global resolution). Every contour — outline, hole or
// open stroke — is resampled into a boundary curve with edges of at most one cell, every contour
// point kept as a node (V¹ exact). A constrained Delaunay triangulation of all nodes (curves as
// constraints) is the triangular mesh; its interior vertices are the grid nodes (V², a bilinear
// combination with one weight), and points where contours cross are free vertices (V³). Junction
// triangles: the mesh triangles outside the interior cells or in a border cell (a cell missing one
// of its eight neighbours).
//
// Energy (Eq. 1-5), minimised by alternating local and global steps:
//   w_r Σ_i (w_i / #R_i) Σ_{j∈R_i} |(q_j − q_c) − A_i (p_j − p_c)|²        (rigid regions)
// + w_s E_s                                                                   (junction)
// + w_p Σ_h |a_h · q − target_h|²                                             (handles)
// R_i of a grid node: the nodes within w of it reached along its column of interior-cell
// edges, then along a row (lattice-shape-matching bars: cells across a gap are never reached,
// and the region sums separate, so each costs O(nodes) whatever w — the fast summation).
// R_i of a curve node: the 2w̃+1 nodes around it on its curve, w̃ = round(w h / l_b).
// Centre c = node i, or the handle node in R_i nearest to i (Eq. 2). w is the global
// stiffness, w_i (from [[stiffness]] regions) the local one.
// Region stride s (`[grid] stride`, default about w / 2): only the grid nodes on every s-th
// row and column (plus any node no such region holds) centre a region that counts, each
// weighed by the nodes it stands for (those nearest it among its members). Seed 003 centres
// one on every node (s = 1); then a region couples its centre with (2w+1)² nodes and the
// factor grows with w (bottle of 2,288 nodes: 50 k non-zeros at w = 1, 657 k at w = 9, and each
// back-substitution with it), while with s ≈ w / 2 it stays near 50 k at every w. Overlapping by
// more than half, the sparser regions bend a figure within 2 % of the every-node ones (test
// StridedRegions...; pictures in docs/solvers.md).
// The junction term E_s ties curves to the grid over the junction triangles, one of:
//  - "mvc", seed 003's Eq. 4: Σ_{v∈V} |v − Σ_j λ_vj v_j|² + Σ_{edges ij} |(v_i − v_j) − l̄_ij u_ij|²,
//    λ the rest mean-value coordinates of the vertices whose one-ring is all junction
//    triangles, u_ij the current direction of edge ij;
//  - "triangles" (default): Σ_t Σ_{edges ij of t} |(v_i − v_j) − R_t (p_i − p_j)|², each
//    junction triangle turned by its own best rotation. Eq. 4 keeps lengths but lets a thin
//    triangle shear and turn over; with a whole outline of such triangles (a raster
//    character's hand, ear or hem) that showed as smeared texture at w = 3 and 6 under a
//    performer's drag, which per-triangle rotations do not (pictures: issue 12's note).
// Both weigh w_s = 6 by default (the seed's 6 : 1 left the curves loose for the same reason). Open
// strokes are curves of the same solve (boundary regions only), and strokes sharing an end point
// share its node: a stick figure (Eq. 6). Handles are soft constraints at their rest points
// (bilinear in a cell, or barycentric in a mesh triangle). The system matrix depends on the rest
// shape only: factorised once.
//
// Riders (a rig's [[rider]] tables): parts taken out of the mesh that turn whole about a hinge.
// The hinge follows the grid under it (or the rider it hangs from), turned as drawn against it;
// then eight sweeps, outermost first, turn each (with what hangs on it) to bring the handles on
// them and a pen nearest their targets, least squares (one with no handle of its own has a weak
// spring to its drawn turn). From the drawn turns every frame: the pose is the targets' alone.
// Their points are set after each solve: no term of the energy, nothing factorised. A still
// rider (scenery) never moves and no pen grabs it.
// Where a drawing's limbs are parts of their own they ride rigid and hinged (the automatic rig's
// parts and silhouette, region by region).
//
// Bones (a rig's [[bone]] tables): a limb inside one shape, given by its medial axis, turning
// whole about its joint as a rider does (its hinge and the grid's turn there from the grid, its
// handle's target, eight sweeps), with no shape of its own. Its limb: the mesh nodes reached
// from its axis through the mesh (so across no gap), never across a cut through the joint
// across the axis, within 2 half-widths of the axis. A point is on the limb when a node it is
// embedded in is; from where the point itself is, it takes all of the turn beyond 2·band from
// the joint and part of it nearer (smoothstep, 0 at the joint), and past 1.5 half-widths of
// the axis less, none at 2. A point of weight w is the grid's point turned by w of the bone's
// turn about the hinge: A_w(p) + (1 − w)(grid(p) − G(p)), G the grid's rigid turn at the
// joint. So a leg inside its body's shape turns at its hip like a leg drawn apart, where the
// grid alone bends it like a beam toward a handle at its foot.
#pragma once

#include <array>
#include <cmath>

#include "solve/ldlt.h"
#include "solve/solver.h"

namespace mar {

class RigidGrid final : public Solver {
 public:
  std::string_view name() const override { return "rigid_grid"; }
  bool prepare(Character& ch, const Rig& rig, std::span<const Vec2> handle_rest, const SolverWeights& w,
               std::string* error) override;
  /// half_width (w, whole cells), rigidity (w_r), junction (w_s), position
  /// (w_p), then one `stiffness.NAME` per named [[stiffness]] region of the
  /// rig. A change rebuilds the regions and factorises again on the calling
  /// thread (it allocates; see refactor_us).
  std::vector<SolverParameter> parameters() const override;
  bool set_parameters(std::span<const double> values, std::string* error) override;
  void solve(std::span<const Vec2> targets, int iterations) override;
  void initial_guess(std::span<const Vec2> targets) override;
  void reset_to_rest() override;
  void shape_points(std::vector<Points>& out) const override;
  Vec2 handle_point(size_t h) const override;
  size_t handle_count() const override { return handles_.size(); }
  void grab(const Vec2& rest_point) override;
  void release() override {
    grab_active_ = false;
    grab_rider_ = -1;
  }
  bool grabbing() const override { return grab_active_; }

  // --- views for tests, inspect and overlays ---
  size_t grid_nodes() const { return grid_count_; }
  size_t boundary_nodes() const { return curve_count_; }
  /// Every drawn contour point a node, as before contours were thinned to about a cell (for
  /// measuring the two side by side); before prepare.
  void keep_every_contour_point(bool on) { every_contour_point_ = on; }
  size_t free_vertices() const { return rest_.size() - grid_count_ - curve_count_; }
  /// Vertices of the triangular mesh (seed 003 Table 1's VER).
  size_t mesh_vertices() const { return mesh_vertex_count_; }
  const Points& rest() const { return rest_; }
  const Points& nodes() const { return x_; }
  std::span<const std::array<int, 3>> mesh_triangles() const { return tris_; }
  std::span<const char> junction() const { return junction_; }  ///< per mesh triangle
  double cell() const { return h_; }
  int half_width() const { return half_width_; }
  /// Every stride-th grid node (along rows and columns) centres a region that counts; 1: every
  /// node, as seed 003.
  int stride() const { return region_stride_ > 0 ? region_stride_ : std::max(1, (half_width_ + 1) / 2); }
  /// 0: about w / 2 (the default); 1..32: that stride. Rebuilds and factorises.
  bool set_stride(int s, std::string* error);
  /// Regions: one per grid node, then one per position on each curve.
  size_t regions() const { return reg_center_.size(); }
  std::span<const int> region(size_t r) const { return {reg_.data() + reg_start_[r], size_t(reg_start_[r + 1] - reg_start_[r])}; }
  int region_center(size_t r) const { return reg_center_[r]; }
  /// How many grid nodes a region stands for (0: it does not count; 1 for every region at
  /// stride 1 and for curve regions).
  double region_share(size_t r) const { return reg_a_[r]; }
  long factor_nonzeros() const { return factor_.nonzeros(); }
  /// The edges of the interior cells (pairs of grid nodes), for overlays.
  std::vector<std::array<int, 2>> grid_edges() const;
  /// The junction triangles, for overlays.
  std::vector<std::array<int, 3>> junction_triangles() const;
  /// Parts riding on the grid ([[rider]]) and limbs turning whole inside one shape ([[bone]]).
  size_t riders() const { return riders_.size(); }
  /// Where a rest point of the character is now (embedded as a handle would
  /// be).
  Vec2 point_at(const Vec2& rest_point) const { return eval(embed(rest_point)); }

  /// The energy of the current pose with the best rotations and edge directions
  /// for it, plus the handle term for `targets`.
  double energy(std::span<const Vec2> targets) const override;

  /// Region sums Σ_{j∈R_r} f_j for every region r (one value per node in, one
  /// per region out), by the fast summation or by visiting every member; and
  /// the transpose, Σ_{r: j∈R_r} g_r (one per region in, one per node out).
  void region_sums(std::span<const double> f, std::span<double> out, bool fast) const;
  void region_scatter(std::span<const double> g, std::span<double> out, bool fast) const;

  /// Fast summation in the solve (default) or the plain sums (seed 003 Table 1
  /// OPT2).
  void set_fast_summation(bool on) { fast_ = on && !plain_; }
  bool fast_summation() const { return fast_; }
  /// Square regions of every grid node within w, ignoring reachability: the
  /// plain regular grid the seed compares against (tests only; rebuilds and
  /// factorises).
  bool set_plain_regions(bool plain, std::string* error);

 private:
  struct Embed {  ///< a point as a combination of up to 4 nodes (bilinear or
                  ///< barycentric)
    int n = 1;
    int v[4] = {0, 0, 0, 0};
    double w[4] = {1, 0, 0, 0};
  };
  Vec2 eval(const Embed& e) const {
    Vec2 p = Vec2::Zero();
    for (int k = 0; k < e.n; ++k) p += e.w[k] * x_[size_t(e.v[k])];
    return p;
  }
  Embed embed(const Vec2& p) const;
  bool prepare_grid(Character& ch, const Rig& rig, std::span<const Vec2> handle_rest, const SolverWeights& w, std::string* error);
  bool prepare_riders(const Character& ch, const Rig& rig, std::string* error);  ///< rigid_grid_riders.cpp, as the ones below
  void prepare_bones(const Rig& rig);
  void skin_bones(const Character& ch);  ///< after the grid: each node's bone and weight, and the points they carry
  /// How much of a bone's turn an embedded point takes (through its nodes), and which bone (-1: none).
  double bone_weight(const Embed& e, int* bone) const;
  /// The bone carrying a rest point at least half way (-1: none), through its embedding.
  int bone_at(const Vec2& rest_point) const;
  void link_riders();
  void place_riders(std::span<const Vec2> targets);  ///< after the grid
  struct Rider {
    std::vector<int> shapes;  ///< its part first, then the shapes riding with it
    int parent = -1;          ///< a rider (earlier in riders_), or -1: the grid
    Vec2 hinge = Vec2::Zero();
    Embed at;                 ///< the hinge on the grid (parent -1)
    Vec2 at0 = Vec2::Zero();  ///< where `at` is on the grid at rest
    int ref = -1;             ///< a node near the hinge: the grid's turn there (no handle)
    int handle = -1;
    Points ring;              ///< its part's outline (for a pen's grab)
    double c = 1, s = 0;      ///< now: x = t + R(c, s) (p − hinge)
    double angle = 0;         ///< of R
    double rel = 0;           ///< its turn against what it hangs on (this frame's sweeps)
    double reach = 0;         ///< from its hinge to the farthest point of its part
    Vec2 t = Vec2::Zero();
    // A bone ([[bone]]): a limb inside one shape. No shape of its own: the grid's points along
    // its limb take its turn (skin_), fully beyond its band, part of the way across it.
    bool bone = false;
    Points axis;                  ///< from the free end to the joint
    std::vector<double> radius;   ///< its half-width at each axis point
    double band = 0;              ///< the blend's length on the limb's side of the joint, halved
    std::vector<int> refs;        ///< grid nodes beside the joint, off the limb: the grid's turn there
    double base = 0;              ///< this frame: the grid's turn at the joint
    double base_c = 1, base_s = 0;  ///< its cosine and sine
    bool still = false;           ///< scenery: never moves (and no pen grabs it)
    void turn(double a) {
      angle = a;
      c = std::cos(a);
      s = std::sin(a);
    }
    Vec2 apply(const Vec2& p) const {
      const Vec2 d = p - hinge;
      return t + Vec2(c * d.x() - s * d.y(), s * d.x() + c * d.y());
    }
  };
  bool cell_inside(int ci, int cj) const {
    return ci >= 0 && cj >= 0 && ci < nx_ && cj < ny_ && cell_in_[size_t(cj) * size_t(nx_) + size_t(ci)];
  }
  int corner_node(int i, int j) const { return node_of_corner_[size_t(j) * size_t(nx_ + 1) + size_t(i)]; }
  void build_runs();
  void build_regions();
  void weigh_regions();  ///< w_i and each region's coefficient w_r w_i / #R_i
  bool factorise(std::string* error);
  /// Windowed sums along runs of nodes (C channels interleaved): out[idx] = Σ
  /// over the run positions within `w` of idx's position.
  struct Runs {
    std::vector<int> start{0};  ///< CSR over `idx`
    std::vector<int> idx;       ///< node (or region) indices in run order
    std::vector<char> closed;   ///< per run: a closed curve (windows wrap)
    std::vector<int> half;      ///< per run: window half-width
  };
  void window_pass(const Runs& runs, const double* in, const std::vector<int>* in_map, double* out,
                   const std::vector<int>* out_map, bool accumulate, int channels) const;
  void gather(const double* f, double* out, int channels,
              bool fast) const;  // per node → per region
  void scatter(const double* g, double* out, int channels,
               bool fast) const;  // per region → per node
  void local_step();
  void global_step(std::span<const Vec2> targets);

  // parameters
  double h_ = 1;
  int half_width_ = 3;
  int region_stride_ = 0;
  double w_r_ = 6, w_s_ = 1, w_p_ = 100;
  /// Per handle, a scale of w_p (SolverWeights::handle_weights: a chain's end is a soft target).
  std::vector<double> handle_w_;
  double handle_w(size_t h) const {
    if (h < handle_rider_.size() && handle_rider_[h] >= 0) return 0.0;  // (it turns a rider, not the grid)
    return h < handle_w_.size() ? handle_w_[h] : 1.0;
  }
  bool fast_ = true, plain_ = false, tri_mode_ = false, every_contour_point_ = false;
  struct Stiff {
    std::string name;
    Vec2 center;
    double radius, weight;
  };
  std::vector<Stiff> stiff_;
  // grid
  Vec2 origin_ = Vec2::Zero();           ///< the grid's corner (0, 0)
  Vec2 mid_ = Vec2::Zero();              ///< the character's centre: sums are taken relative to it
  int nx_ = 0, ny_ = 0;                  ///< cells
  std::vector<char> cell_in_;            ///< nx * ny
  std::vector<int> node_of_corner_;      ///< (nx+1) * (ny+1): node index or -1
  std::vector<std::array<int, 2>> gxy_;  ///< per grid node: its lattice corner
  size_t grid_count_ = 0, curve_count_ = 0;
  struct Curve {
    int first, count;  ///< positions in cnode_
    bool closed;
    double spacing;  ///< mean node spacing l_b
  };
  std::vector<Curve> curves_;
  std::vector<int> cnode_;  ///< per curve position: its node
  Runs rows_, cols_,
      curve_runs_;                 ///< grid rows and columns of interior-cell edges; curves
  std::vector<int> curve_region_;  ///< per curve position: its region index
  // nodes and regions
  Points rest_, x_;
  Points p_;                          ///< rest_ − mid_
  std::vector<double> node_w_;        ///< local stiffness w_i per node
  std::vector<int> reg_start_, reg_;  ///< region members (CSR)
  std::vector<int> reg_center_;       ///< centre node (Eq. 2)
  std::vector<int> reg_size_;         ///< #R_i
  std::vector<Vec2> reg_psum_;        ///< Σ_{j∈R_i} p_j (relative to mid_)
  std::vector<double> reg_a_;         ///< nodes a region stands for (0: it does not count)
  std::vector<double> reg_k_;         ///< a_r w_r w_i / #R_i
  std::vector<double> rc_, rs_;       ///< per region rotation
  // junction
  std::vector<std::array<int, 3>> tris_;  ///< mesh triangles (node indices)
  std::vector<char> junction_;
  size_t mesh_vertex_count_ = 0;
  std::vector<std::array<int, 2>> edges_;  ///< junction edges
  std::vector<double> edge_len_;
  std::vector<int> mvc_start_,
      mvc_node_;               ///< per MVC vertex: itself first, then its ring
  std::vector<double> mvc_w_;  ///< 1, then −λ_vj
  // shape points and handles
  std::vector<std::vector<Embed>> binds_;
  std::vector<Embed> handles_;
  Points handle_rest_;
  std::vector<int> handle_node_;
  std::vector<double> pull_;  ///< per node: the pull of a part no handle reaches (0: held)
  PrefactoredLdlt factor_;
  // per-iteration buffers
  mutable std::vector<double> ch_in_, ch_mid_, ch_out_, prefix_;
  std::vector<double> bx_, by_;
  bool grab_active_ = false;
  Embed grab_;
  // riders
  std::vector<Rider> riders_;
  std::vector<int> rider_of_;        ///< per shape: its rider, or -1
  std::vector<Points> rider_rest_;   ///< per shape: its rest points, for a riding shape
  std::vector<int> handle_rider_;    ///< per handle: the rider it turns, or -1
  std::vector<int> pull_start_, pull_h_, pull_r_;  ///< per rider: the handles on it and on what hangs on it, and the rider carrying each
  std::vector<int> desc_start_, desc_;             ///< per rider: the riders hanging on it, through others too
  static constexpr int kRiderSweeps = 8;
  static constexpr double kRiderSpring = 0.05;  ///< against a handle's pull at the rider's reach
  /// How much of bone d's turn a rest point takes, from where it is against the bone's axis.
  static double limb_weight(const Rider& d, const Vec2& q);
  struct Skin {  ///< a grid point a bone carries: out = A_w(p) + (1 − w)(grid(p) − G(p))
    int shape, point, bone;
    double w;
    Vec2 rest;
  };
  std::vector<Skin> skin_;
  std::vector<int> node_bone_;       ///< per node: the bone carrying it, or -1
  std::vector<double> node_bone_w_;  ///< per node: how much of its turn
  int grab_rider_ = -1;              ///< a pen holding a rider
  Vec2 grab_rest_ = Vec2::Zero();
  RankOneUpdate grab_update_;
};

}  // namespace mar
