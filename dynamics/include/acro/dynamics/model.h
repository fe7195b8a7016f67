#pragma once

// The multibody model: a const tree of rigid segments (docs/notation.md). Segment 0 is the root,
// attached to the world W by a free joint (position + unit quaternion). Every other segment is
// attached to its parent by a fixed joint or by an Euler-angle joint of 1–3 rotation axes taken
// from {x, y, z} in any order with no axis repeated twice in a row ("y", "zx", "xyz", "zxz").
// Segments are stored in topological order (a parent before its children), which every
// recursive algorithm relies on. Built once by ModelBuilder (model_builder.h), then only read.

#include <array>
#include <string>
#include <vector>

#include "acro/base/demand.h"
#include "acro/dynamics/spatial.h"

namespace acro::dynamics {

enum class JointType {
  kFree,   ///< the root: 7 coordinates (p_WB, quaternion w x y z), 6 velocities
  kFixed,  ///< welded to its parent: no coordinate
  kEuler,  ///< 1–3 successive rotations about the joint frame's own (moving) axes
};

/// One segment and the joint that attaches it to its parent.
template <typename T>
struct Segment {
  std::string name;
  int parent = -1;  ///< index of the parent segment, −1 for the root

  // The joint. Its frame J is fixed in the parent at X_PJ; the segment frame B coincides with J
  // rotated by the joint: R_JB = R_a1(θ1)·R_a2(θ2)·R_a3(θ3) (intrinsic sequence), p_JoBo = 0.
  JointType joint_type = JointType::kFixed;
  std::string axis_sequence;         ///< e.g. "yxz"; empty for fixed and free joints
  int num_axes = 0;                  ///< 0 fixed, 1–3 Euler; the free joint has 6 velocities
  std::array<int, 3> axes{0, 0, 0};  ///< 0 = x, 1 = y, 2 = z, in sequence order
  int q_start = 0;                   ///< first coordinate of this joint in q
  int v_start = 0;                   ///< first velocity of this joint in v
  RigidTransform<T> X_PJ;            ///< joint frame in the parent segment frame
  bool joint_rotation_is_identity = true;  ///< R_PJ == I (saves a 3×3 product per call)

  // Mass properties in the segment frame.
  T mass;
  Vector3<T> p_BoBcm_B;
  Matrix3<T> I_BBcm_B;       ///< rotational inertia about the centre of mass Bcm
  SpatialInertia<T> M_Bo_B;  ///< the same as a spatial inertia about Bo
};

/// A named point fixed in a segment: a marker, an anatomical landmark, a joint centre.
template <typename T>
struct Point {
  std::string name;
  int segment = 0;
  Vector3<T> p_BoP_B;
};

/// The const multibody model. q has nq = 7 + n entries, v has nv = 6 + n (n joint angles).
template <typename T>
class Model {
 public:
  using Scalar = T;

  int num_segments() const { return static_cast<int>(segments_.size()); }
  int num_points() const { return static_cast<int>(points_.size()); }
  int nq() const { return nq_; }
  int nv() const { return nv_; }
  /// Number of joint angles n (= nv − 6).
  int num_joint_dofs() const { return nv_ - 6; }
  const Segment<T>& segment(int i) const { return segments_[static_cast<size_t>(i)]; }
  const std::vector<Segment<T>>& segments() const { return segments_; }
  const Point<T>& point(int i) const { return points_[static_cast<size_t>(i)]; }
  const std::vector<Point<T>>& points() const { return points_; }
  /// Gravitational acceleration in W, default (0, 0, −9.81) m/s².
  const Vector3<T>& gravity_W() const { return gravity_W_; }
  const T& total_mass() const { return total_mass_; }
  /// Deepest root-to-leaf chain length in segments (1 for a lone root).
  int max_depth() const { return max_depth_; }

  /// Index of the segment with this name, or −1.
  int FindSegment(const std::string& name) const {
    for (int i = 0; i < num_segments(); ++i)
      if (segments_[static_cast<size_t>(i)].name == name) return i;
    return -1;
  }
  /// Index of the point with this name, or −1.
  int FindPoint(const std::string& name) const {
    for (int i = 0; i < num_points(); ++i)
      if (points_[static_cast<size_t>(i)].name == name) return i;
    return -1;
  }
  /// The segment that velocity index k moves, and the axis name ("root:vx", "r_hip:y", …).
  std::string VelocityName(int k) const;

  /// The same model in another scalar type (e.g. ceres::Jet for automatic differentiation).
  template <typename U>
  Model<U> Cast() const;

 private:
  friend class ModelBuilder;
  template <typename U>
  friend class Model;

  std::vector<Segment<T>> segments_;
  std::vector<Point<T>> points_;
  Vector3<T> gravity_W_;
  T total_mass_;
  int nq_ = 7;
  int nv_ = 6;
  int max_depth_ = 1;
};

template <typename T>
std::string Model<T>::VelocityName(int k) const {
  ACRO_DEMAND(k >= 0 && k < nv_);
  static const char* kRoot[6] = {"vx", "vy", "vz", "wx", "wy", "wz"};
  if (k < 6) return segments_[0].name + ":" + kRoot[k];
  for (const Segment<T>& s : segments_) {
    if (s.joint_type == JointType::kEuler && k >= s.v_start && k < s.v_start + s.num_axes)
      return s.name + ":" + s.axis_sequence[static_cast<size_t>(k - s.v_start)];
  }
  ACRO_DEMAND(false);
  return {};
}

template <typename T>
template <typename U>
Model<U> Model<T>::Cast() const {
  Model<U> out;
  out.segments_.reserve(segments_.size());
  for (const Segment<T>& s : segments_) {
    Segment<U> c;
    c.name = s.name;
    c.parent = s.parent;
    c.joint_type = s.joint_type;
    c.axis_sequence = s.axis_sequence;
    c.num_axes = s.num_axes;
    c.axes = s.axes;
    c.q_start = s.q_start;
    c.v_start = s.v_start;
    c.X_PJ = s.X_PJ.template cast<U>();
    c.joint_rotation_is_identity = s.joint_rotation_is_identity;
    c.mass = U(s.mass);
    c.p_BoBcm_B = s.p_BoBcm_B.template cast<U>();
    c.I_BBcm_B = s.I_BBcm_B.template cast<U>();
    c.M_Bo_B = SpatialInertia<U>(U(s.M_Bo_B.mass()),
                                 s.M_Bo_B.first_moment().template cast<U>(),
                                 s.M_Bo_B.rotational_inertia().template cast<U>());
    out.segments_.push_back(c);
  }
  for (const Point<T>& p : points_) {
    Point<U> c;
    c.name = p.name;
    c.segment = p.segment;
    c.p_BoP_B = p.p_BoP_B.template cast<U>();
    out.points_.push_back(c);
  }
  out.gravity_W_ = gravity_W_.template cast<U>();
  out.total_mass_ = U(total_mass_);
  out.nq_ = nq_;
  out.nv_ = nv_;
  out.max_depth_ = max_depth_;
  return out;
}

}  // namespace acro::dynamics
