#pragma once

// Spatial (6D) algebra as strong types, after Featherstone 2008, Rigid Body Dynamics Algorithms
// (RBDA), chapter 2. Every 6-vector stores its rotational part first (Plücker order [ω; v] for
// motion, [n; f] for force), as in RBDA and Drake. A motion and a force are different types, so
// adding a force to a velocity does not compile; their only product is the scalar power Dot().
//
// Monogram names follow docs/notation.md: V_AB_E is the spatial velocity of frame B in frame A,
// about Bo, expressed in E; F_Bo_E a spatial force on B about Bo, expressed in E; X_AB the pose of
// B in A.

#include <Eigen/Core>
#include <Eigen/Geometry>

namespace acro::dynamics {

template <typename T>
using Vector3 = Eigen::Matrix<T, 3, 1>;
template <typename T>
using Vector6 = Eigen::Matrix<T, 6, 1>;
template <typename T>
using Matrix3 = Eigen::Matrix<T, 3, 3>;
template <typename T>
using Matrix6 = Eigen::Matrix<T, 6, 6>;
template <typename T>
using VectorX = Eigen::Matrix<T, Eigen::Dynamic, 1>;
template <typename T>
using MatrixX = Eigen::Matrix<T, Eigen::Dynamic, Eigen::Dynamic>;
template <typename T>
using Matrix3X = Eigen::Matrix<T, 3, Eigen::Dynamic>;
template <typename T>
using Matrix6X = Eigen::Matrix<T, 6, Eigen::Dynamic>;

namespace internal {
/// C++20's std::type_identity, spelled out so that these headers also compile as C++17 (the
/// Simbody oracle test needs that: Simbody 3.7's headers are ambiguous under C++20).
template <typename U>
struct TypeIdentity {
  using type = U;
};
}  // namespace internal

// References to vectors and matrices in algorithm signatures. The type-identity wrapper keeps them
// out of template argument deduction, so the scalar type is deduced from the model alone and plain
// Eigen vectors, blocks and maps can be passed.
template <typename T>
using VectorXcRef = typename internal::TypeIdentity<Eigen::Ref<const VectorX<T>>>::type;
template <typename T>
using VectorXRef = typename internal::TypeIdentity<Eigen::Ref<VectorX<T>>>::type;
template <typename T>
using MatrixXRef = typename internal::TypeIdentity<Eigen::Ref<MatrixX<T>>>::type;
template <typename T>
using Matrix3XRef = typename internal::TypeIdentity<Eigen::Ref<Matrix3X<T>>>::type;
template <typename T>
using Matrix6XRef = typename internal::TypeIdentity<Eigen::Ref<Matrix6X<T>>>::type;

/// Skew-symmetric matrix [a]× with [a]× b = a × b.
template <typename T>
Matrix3<T> Skew(const Vector3<T>& a) {
  Matrix3<T> s;
  s << T(0), -a.z(), a.y(), a.z(), T(0), -a.x(), -a.y(), a.x(), T(0);
  return s;
}

template <typename T>
class SpatialForce;

/// A spatial motion vector [ω; v] (velocity or acceleration): ω the angular part, v the linear
/// part of the point at the origin of the frame it is expressed about. RBDA ch. 2.
template <typename T>
class SpatialMotion {
 public:
  /// Uninitialised, like Eigen's fixed-size types.
  SpatialMotion() = default;
  SpatialMotion(const Vector3<T>& w, const Vector3<T>& v) : w_(w), v_(v) {}
  explicit SpatialMotion(const Vector6<T>& wv)
      : w_(wv.template head<3>()), v_(wv.template tail<3>()) {}

  static SpatialMotion Zero() { return SpatialMotion(Vector3<T>::Zero(), Vector3<T>::Zero()); }

  const Vector3<T>& rotational() const { return w_; }
  const Vector3<T>& translational() const { return v_; }
  Vector3<T>& mutable_rotational() { return w_; }
  Vector3<T>& mutable_translational() { return v_; }
  Vector6<T> get_coeffs() const {
    Vector6<T> out;
    out << w_, v_;
    return out;
  }

  SpatialMotion& operator+=(const SpatialMotion& o) {
    w_ += o.w_;
    v_ += o.v_;
    return *this;
  }
  SpatialMotion& operator-=(const SpatialMotion& o) {
    w_ -= o.w_;
    v_ -= o.v_;
    return *this;
  }
  friend SpatialMotion operator+(SpatialMotion a, const SpatialMotion& b) { return a += b; }
  friend SpatialMotion operator-(SpatialMotion a, const SpatialMotion& b) { return a -= b; }
  friend SpatialMotion operator-(const SpatialMotion& a) { return SpatialMotion(-a.w_, -a.v_); }
  friend SpatialMotion operator*(const T& s, const SpatialMotion& a) {
    return SpatialMotion(s * a.w_, s * a.v_);
  }

  /// Motion cross product m₁ × m₂ = [ω₁×ω₂; ω₁×v₂ + v₁×ω₂], RBDA ch. 2 (crm).
  SpatialMotion Cross(const SpatialMotion& m) const {
    return SpatialMotion(w_.cross(m.w_), w_.cross(m.v_) + v_.cross(m.w_));
  }
  /// Force cross product m ×* f = [ω×n + v×f; ω×f], RBDA ch. 2 (crf).
  SpatialForce<T> CrossForce(const SpatialForce<T>& f) const;
  /// Power m · f (a scalar, the only product of a motion and a force), RBDA ch. 2.
  T Dot(const SpatialForce<T>& f) const;

 private:
  Vector3<T> w_;
  Vector3<T> v_;
};

/// A spatial force vector [n; f]: n the moment about the origin of the frame it is expressed
/// about, f the force. Momentum is force-like and uses SpatialMomentum. RBDA ch. 2.
template <typename T>
class SpatialForce {
 public:
  SpatialForce() = default;
  SpatialForce(const Vector3<T>& n, const Vector3<T>& f) : n_(n), f_(f) {}
  explicit SpatialForce(const Vector6<T>& nf)
      : n_(nf.template head<3>()), f_(nf.template tail<3>()) {}

  static SpatialForce Zero() { return SpatialForce(Vector3<T>::Zero(), Vector3<T>::Zero()); }

  const Vector3<T>& rotational() const { return n_; }
  const Vector3<T>& translational() const { return f_; }
  Vector3<T>& mutable_rotational() { return n_; }
  Vector3<T>& mutable_translational() { return f_; }
  Vector6<T> get_coeffs() const {
    Vector6<T> out;
    out << n_, f_;
    return out;
  }

  /// The same force about a point Q instead of the current origin O, given p_OQ in the same
  /// expressed-in frame: n_Q = n_O − p_OQ × f (RBDA ch. 2, a pure translation).
  SpatialForce Shift(const Vector3<T>& p_OQ) const { return SpatialForce(n_ - p_OQ.cross(f_), f_); }

  SpatialForce& operator+=(const SpatialForce& o) {
    n_ += o.n_;
    f_ += o.f_;
    return *this;
  }
  SpatialForce& operator-=(const SpatialForce& o) {
    n_ -= o.n_;
    f_ -= o.f_;
    return *this;
  }
  friend SpatialForce operator+(SpatialForce a, const SpatialForce& b) { return a += b; }
  friend SpatialForce operator-(SpatialForce a, const SpatialForce& b) { return a -= b; }
  friend SpatialForce operator-(const SpatialForce& a) { return SpatialForce(-a.n_, -a.f_); }
  friend SpatialForce operator*(const T& s, const SpatialForce& a) {
    return SpatialForce(s * a.n_, s * a.f_);
  }

 private:
  Vector3<T> n_;
  Vector3<T> f_;
};

/// Spatial momentum [h; l] of a body or system about a point: h the angular momentum about that
/// point, l the linear momentum (RBDA ch. 2, spatial momentum). Its own type so that it is not
/// mistaken for a force.
template <typename T>
class SpatialMomentum {
 public:
  SpatialMomentum() = default;
  SpatialMomentum(const Vector3<T>& h, const Vector3<T>& l) : h_(h), l_(l) {}
  static SpatialMomentum Zero() { return SpatialMomentum(Vector3<T>::Zero(), Vector3<T>::Zero()); }
  const Vector3<T>& rotational() const { return h_; }
  const Vector3<T>& translational() const { return l_; }
  SpatialMomentum& operator+=(const SpatialMomentum& o) {
    h_ += o.h_;
    l_ += o.l_;
    return *this;
  }
  /// The same momentum about Q instead of O: h_Q = h_O − p_OQ × l.
  SpatialMomentum Shift(const Vector3<T>& p_OQ) const {
    return SpatialMomentum(h_ - p_OQ.cross(l_), l_);
  }

 private:
  Vector3<T> h_;
  Vector3<T> l_;
};

template <typename T>
SpatialForce<T> SpatialMotion<T>::CrossForce(const SpatialForce<T>& f) const {
  return SpatialForce<T>(w_.cross(f.rotational()) + v_.cross(f.translational()),
                         w_.cross(f.translational()));
}

template <typename T>
T SpatialMotion<T>::Dot(const SpatialForce<T>& f) const {
  return w_.dot(f.rotational()) + v_.dot(f.translational());
}

/// Spatial inertia of a rigid body about the origin O of the frame it is expressed in, stored as
/// mass m, first moment h = m·p_OBcm and rotational inertia about O, Ī_O = I_Bcm − m [c]×[c]×
/// (RBDA ch. 2, spatial inertia in its compact form). Composite inertias are plain sums.
template <typename T>
class SpatialInertia {
 public:
  SpatialInertia() = default;
  SpatialInertia(const T& mass, const Vector3<T>& first_moment, const Matrix3<T>& I_O)
      : m_(mass), h_(first_moment), I_(I_O) {}

  /// From mass, p_OBcm and the rotational inertia about Bcm, all in the same frame.
  static SpatialInertia FromMassComInertia(const T& mass,
                                           const Vector3<T>& p_OBcm,
                                           const Matrix3<T>& I_Bcm) {
    const Matrix3<T> c = Skew(p_OBcm);
    return SpatialInertia(mass, mass * p_OBcm, I_Bcm - mass * c * c);
  }
  static SpatialInertia Zero() {
    return SpatialInertia(T(0), Vector3<T>::Zero(), Matrix3<T>::Zero());
  }

  const T& mass() const { return m_; }
  const Vector3<T>& first_moment() const { return h_; }
  /// Rotational inertia about the origin O.
  const Matrix3<T>& rotational_inertia() const { return I_; }
  /// p_OBcm (undefined for zero mass).
  Vector3<T> com() const { return h_ / m_; }

  /// I·m: momentum (or force, for an acceleration) [Ī ω + h × v; m v − h × ω], RBDA ch. 2.
  SpatialForce<T> operator*(const SpatialMotion<T>& m) const {
    return SpatialForce<T>(I_ * m.rotational() + h_.cross(m.translational()),
                           m_ * m.translational() - h_.cross(m.rotational()));
  }
  /// I·[ω; 0] = [Ī ω; −h × ω]: the cheaper product with a pure rotation.
  SpatialForce<T> MultiplyRotation(const Vector3<T>& w) const {
    return SpatialForce<T>(I_ * w, -h_.cross(w));
  }
  SpatialMomentum<T> Momentum(const SpatialMotion<T>& V) const {
    const SpatialForce<T> f = (*this) * V;
    return SpatialMomentum<T>(f.rotational(), f.translational());
  }

  SpatialInertia& operator+=(const SpatialInertia& o) {
    m_ += o.m_;
    h_ += o.h_;
    I_ += o.I_;
    return *this;
  }
  friend SpatialInertia operator+(SpatialInertia a, const SpatialInertia& b) { return a += b; }

  /// The 6×6 matrix in Plücker order (for tests and small solves).
  Matrix6<T> ToMatrix() const {
    Matrix6<T> M;
    const Matrix3<T> hx = Skew(h_);
    M.template topLeftCorner<3, 3>() = I_;
    M.template topRightCorner<3, 3>() = hx;
    M.template bottomLeftCorner<3, 3>() = -hx;
    M.template bottomRightCorner<3, 3>() = m_ * Matrix3<T>::Identity();
    return M;
  }

 private:
  T m_;
  Vector3<T> h_;
  Matrix3<T> I_;
};

/// Pose X_AB of frame B in frame A: rotation R_AB (columns are B's axes in A) and position
/// p_AoBo_A. Applying it re-expresses spatial vectors from B to A (RBDA ch. 2 with E = R_ABᵀ,
/// r = p_AoBo_A); the Inverse* methods go from A to B without forming the inverse.
template <typename T>
class RigidTransform {
 public:
  RigidTransform() = default;
  RigidTransform(const Matrix3<T>& R_AB, const Vector3<T>& p_AoBo_A) : R_(R_AB), p_(p_AoBo_A) {}
  static RigidTransform Identity() {
    return RigidTransform(Matrix3<T>::Identity(), Vector3<T>::Zero());
  }

  const Matrix3<T>& rotation() const { return R_; }
  const Vector3<T>& translation() const { return p_; }
  Matrix3<T>& mutable_rotation() { return R_; }
  Vector3<T>& mutable_translation() { return p_; }

  /// X_AC = X_AB · X_BC.
  RigidTransform operator*(const RigidTransform& X_BC) const {
    return RigidTransform(R_ * X_BC.R_, R_ * X_BC.p_ + p_);
  }
  RigidTransform Inverse() const {
    const Matrix3<T> Rt = R_.transpose();
    return RigidTransform(Rt, -(Rt * p_));
  }
  /// p_AoQ_A from p_BoQ_B.
  Vector3<T> operator*(const Vector3<T>& p_BoQ_B) const { return R_ * p_BoQ_B + p_; }

  /// V about Bo in B → the same motion about Ao in A: ω_A = R ω_B, v_A = R v_B + p × ω_A.
  SpatialMotion<T> Apply(const SpatialMotion<T>& m) const {
    const Vector3<T> w = R_ * m.rotational();
    return SpatialMotion<T>(w, R_ * m.translational() + p_.cross(w));
  }
  /// V about Ao in A → about Bo in B: ω_B = Rᵀ ω_A, v_B = Rᵀ (v_A − p × ω_A).
  SpatialMotion<T> ApplyInverse(const SpatialMotion<T>& m) const {
    return SpatialMotion<T>(R_.transpose() * m.rotational(),
                            R_.transpose() * (m.translational() - p_.cross(m.rotational())));
  }
  /// F about Bo in B → about Ao in A: f_A = R f_B, n_A = R n_B + p × f_A.
  SpatialForce<T> Apply(const SpatialForce<T>& F) const {
    const Vector3<T> f = R_ * F.translational();
    return SpatialForce<T>(R_ * F.rotational() + p_.cross(f), f);
  }
  /// F about Ao in A → about Bo in B: f_B = Rᵀ f_A, n_B = Rᵀ (n_A − p × f_A).
  SpatialForce<T> ApplyInverse(const SpatialForce<T>& F) const {
    return SpatialForce<T>(R_.transpose() * (F.rotational() - p_.cross(F.translational())),
                           R_.transpose() * F.translational());
  }
  SpatialMomentum<T> Apply(const SpatialMomentum<T>& L) const {
    const SpatialForce<T> F = Apply(SpatialForce<T>(L.rotational(), L.translational()));
    return SpatialMomentum<T>(F.rotational(), F.translational());
  }
  /// Inertia about Bo in B → about Ao in A (RBDA ch. 2, Xᵀ I X):
  /// h_A = R h_B + m p, Ī_A = R Ī_B Rᵀ − [h']×[p]× − [p]×[h']× − m [p]×[p]×, h' = R h_B,
  /// with [a]×[b]× = b aᵀ − (a·b) 1 so that no 3 × 3 skew products are formed.
  SpatialInertia<T> Apply(const SpatialInertia<T>& I) const {
    const Vector3<T> hr = R_ * I.first_moment();
    const T& m = I.mass();
    Matrix3<T> Ia = R_ * I.rotational_inertia() * R_.transpose();
    // −([h']×[p]× + [p]×[h']× + m [p]×[p]×) = −(p h'ᵀ + h' pᵀ + m p pᵀ) + (2 h'·p + m |p|²) 1.
    const Vector3<T> mp_half = T(0.5) * m * p_;
    Ia.noalias() -= p_ * (hr + mp_half).transpose() + (hr + mp_half) * p_.transpose();
    Ia.diagonal().array() += T(2) * hr.dot(p_) + m * p_.squaredNorm();
    return SpatialInertia<T>(m, hr + m * p_, Ia);
  }

  template <typename U>
  RigidTransform<U> cast() const {
    return RigidTransform<U>(R_.template cast<U>(), p_.template cast<U>());
  }

 private:
  Matrix3<T> R_;
  Vector3<T> p_;
};

}  // namespace acro::dynamics
