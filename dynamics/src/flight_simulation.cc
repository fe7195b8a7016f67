#include "acro/dynamics/flight_simulation.h"

#include <cmath>
#include <sstream>

namespace acro::dynamics {

bool FlightSimulationOptions::IsValid(std::string* why) const {
  auto fail = [why](const std::string& reason) {
    if (why != nullptr) *why = reason;
    return false;
  };
  if (!(std::isfinite(duration_s) && duration_s > 0.0)) return fail("duration_s must be positive");
  if (!(std::isfinite(step_s) && step_s > 0.0)) return fail("step_s must be positive");
  if (!(std::isfinite(output_interval_s) && output_interval_s >= 0.0))
    return fail("output_interval_s must be zero or positive");
  if (max_steps <= 0) return fail("max_steps must be positive");
  if (adaptive) {
    if (!(std::isfinite(tolerance) && tolerance > 0.0)) return fail("tolerance must be positive");
    if (!(min_step_s > 0.0 && min_step_s <= max_step_s && std::isfinite(max_step_s)))
      return fail("need 0 < min_step_s <= max_step_s");
  }
  return true;
}

std::string FlightSimulationSummary::BriefReport() const {
  std::ostringstream out;
  switch (status) {
    case FlightSimulationStatus::kSuccess:
      out << "Flight simulation succeeded";
      break;
    case FlightSimulationStatus::kInvalidOptions:
      out << "Flight simulation not run: invalid options";
      break;
    case FlightSimulationStatus::kStepTooSmall:
      out << "Flight simulation stopped: step too small";
      break;
    case FlightSimulationStatus::kMaxStepsReached:
      out << "Flight simulation stopped: too many steps";
      break;
  }
  out << " (t = " << final_time_s << " s, " << num_steps << " steps, " << num_rejected_steps
      << " rejected)";
  if (!message.empty()) out << ": " << message;
  return out.str();
}

template FlightSimulationResult<double> SimulateFlight<double>(const Model<double>&,
                                                               const FlightSimulationOptions&,
                                                               const Eigen::Matrix<double, 7, 1>&,
                                                               const Vector6<double>&,
                                                               const JointTrajectory<double>&);
template Vector6<double> CalcRootVelocityFromMomentum<double>(
    const Model<double>&,
    Workspace<double>&,
    const Eigen::Ref<const VectorX<double>>&,
    const Eigen::Ref<const VectorX<double>>&,
    const Vector3<double>&,
    const Vector3<double>&);

}  // namespace acro::dynamics
