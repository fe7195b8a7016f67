#include "acro/athlete/standard_human.h"

#include "acro/base/demand.h"
#include "acro/dynamics/model_builder.h"

namespace acro::analysis {

dynamics::Model<double> MakeStandardHumanModel(const AthleteBody& body) {
  ACRO_DEMAND(body.segments.size() == kStandardJoints.size());
  // Mass properties in each segment's frame B (parallel to H, origin at the proximal joint).
  auto mass_of = [&](const BodySegment& s) {
    dynamics::MassProperties m;
    m.mass_kg = s.in_H.mass_kg;
    m.p_BoBcm_B = s.in_H.p_HoCm_H - s.p_HoJ_H;
    m.I_BBcm_B = 0.5 * (s.in_H.I_Cm_H + s.in_H.I_Cm_H.transpose());
    return m;
  };
  dynamics::ModelBuilder builder(body.segments[0].name, mass_of(body.segments[0]));
  // Joints: the child's joint centre relative to the parent's origin, frames parallel to H.
  for (size_t i = 1; i < body.segments.size(); ++i) {
    const BodySegment& s = body.segments[i];
    ACRO_DEMAND(s.name == kStandardJoints[i].segment && s.parent >= 0);
    const BodySegment& parent = body.segments[static_cast<size_t>(s.parent)];
    dynamics::JointSpec joint;
    joint.axis_sequence = std::string(kStandardJoints[i].axis_sequence);
    joint.p_PoJo_P = s.p_HoJ_H - parent.p_HoJ_H;
    builder.AddSegment(s.name, parent.name, joint, mass_of(s));
  }
  // Named points: joint centres, landmarks at segment ends, segment centres of mass.
  builder.AddPoint("midhip", "pelvis", Eigen::Vector3d::Zero());
  for (size_t i = 1; i < body.segments.size(); ++i)
    builder.AddPoint(std::string(kStandardJoints[i].joint_centre),
                     body.segments[i].name,
                     Eigen::Vector3d::Zero());
  auto end_of = [&](const char* name) {
    const BodySegment& s = body.segments[static_cast<size_t>(body.Find(name))];
    return Eigen::Vector3d(s.p_HoE_H - s.p_HoJ_H);
  };
  builder.AddPoint("head_vertex", "head", end_of("head"));
  for (const char* side : {"r", "l"}) {
    const std::string s(side);
    builder.AddPoint(s + "_hand_end", s + "_hand", end_of((s + "_hand").c_str()));
    builder.AddPoint(s + "_toe", s + "_foot", end_of((s + "_foot").c_str()));
  }
  for (const BodySegment& s : body.segments)
    builder.AddPoint(s.name + "_com", s.name, s.in_H.p_HoCm_H - s.p_HoJ_H);
  return builder.Build();
}

}  // namespace acro::analysis
