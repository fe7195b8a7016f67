#include "acro/vision/image_flights.h"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <limits>

#include <fmt/format.h>
#include <Eigen/QR>

#include "acro/base/input_error.h"

namespace acro::vision {

namespace {

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

std::string Lower(std::string s) {
  for (char& c : s) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  return s;
}

// Which keypoints are the hips, the feet (soles: ankles, heels, toes) and the head.
struct BodyParts {
  std::vector<int> hips, feet, head;
  /// Indices into `feet` by foot: the left's, the right's, and any keypoint of no side.
  std::vector<std::vector<int>> foot_groups;
};

BodyParts FindParts(const std::vector<std::string>& names) {
  BodyParts parts;
  for (int j = 0; j < static_cast<int>(names.size()); ++j) {
    const std::string n = Lower(names[size_t(j)]);
    if (n.find("hip") != std::string::npos) parts.hips.push_back(j);
    if (n.find("ankle") != std::string::npos || n.find("heel") != std::string::npos ||
        n.find("toe") != std::string::npos || n.find("foot_index") != std::string::npos) {
      const bool left = n.rfind("left", 0) == 0 || n.rfind("l", 0) == 0;
      const bool right = n.rfind("right", 0) == 0 || n.rfind("r", 0) == 0;
      parts.foot_groups.resize(3);
      parts.foot_groups[left ? 0 : right ? 1 : 2].push_back(static_cast<int>(parts.feet.size()));
      parts.feet.push_back(j);
    }
    if (n.find("nose") != std::string::npos || n.find("eye") != std::string::npos ||
        n.find("ear") != std::string::npos || n == "head")
      parts.head.push_back(j);
  }
  return parts;
}

// The body's centre of mass in the picture from its keypoints: each segment's centre between its
// two keypoints at de Leva's ratio, weighted by his mass fractions (de Leva 1996, Adjustments to
// Zatsiorsky–Seluyanov's segment inertia parameters, J. Biomech. 29(9), table 4, males: % of the
// body's mass, and the centre's distance from the proximal end in % of the segment's length).
// Under a camera's weak perspective the picture of the centre of mass is the mass-weighted mean of
// the segments' pictures; it flies a parabola where the hips, which move within the body as it
// tucks and opens, do not.
struct MassPoint {
  int proximal = -1, distal = -1;  // keypoints; distal −1: the proximal point itself
  double ratio = 0.0, mass = 0.0;
};

int FindSided(const std::vector<std::string>& names,
              bool left,
              const std::vector<std::string>& parts) {
  for (int j = 0; j < static_cast<int>(names.size()); ++j) {
    const std::string n = Lower(names[size_t(j)]);
    const bool is_left = n.rfind("left", 0) == 0 || n.rfind("l", 0) == 0;
    const bool is_right = n.rfind("right", 0) == 0 || n.rfind("r", 0) == 0;
    if ((left && !is_left) || (!left && !is_right)) continue;
    for (const std::string& part : parts)
      if (n.find(part) != std::string::npos) return j;
  }
  return -1;
}

struct MassModel {
  std::vector<MassPoint> points;           // limbs and the hands and feet
  std::vector<int> shoulders, hips, head;  // the trunk between the shoulders' and hips' middles
};

MassModel MakeMassModel(const std::vector<std::string>& names, const std::vector<int>& head) {
  MassModel m;
  m.head = head;
  for (const bool left : {true, false}) {
    const int shoulder = FindSided(names, left, {"shoulder"});
    const int elbow = FindSided(names, left, {"elbow"});
    const int wrist = FindSided(names, left, {"wrist"});
    const int hip = FindSided(names, left, {"hip"});
    const int knee = FindSided(names, left, {"knee"});
    const int ankle = FindSided(names, left, {"ankle"});
    const int heel = FindSided(names, left, {"heel"});
    const int toe = FindSided(names, left, {"bigtoe", "big_toe", "foot_index"});
    m.points.push_back({shoulder, elbow, 0.5772, 2.71});
    m.points.push_back({elbow, wrist, 0.4574, 1.62});
    m.points.push_back({wrist, -1, 0.0, 0.61});
    m.points.push_back({hip, knee, 0.4095, 14.16});
    m.points.push_back({knee, ankle, 0.4459, 4.33});
    if (heel >= 0 && toe >= 0)
      m.points.push_back({heel, toe, 0.4415, 1.37});
    else
      m.points.push_back({ankle, -1, 0.0, 1.37});
    m.shoulders.push_back(shoulder);
    m.hips.push_back(hip);
  }
  return m;
}

// The centre of mass's image y, NaN when less than 80 % of the body's mass is seen.
double CentreOfMassY(const MassModel& m,
                     const capture::DetectedPerson& person,
                     double min_confidence) {
  auto seen = [&](int j) {
    return j >= 0 && j < person.cols() && person(2, j) >= min_confidence &&
           std::isfinite(person(1, j));
  };
  double sum = 0, mass = 0;
  for (const MassPoint& p : m.points) {
    if (!seen(p.proximal) || (p.distal >= 0 && !seen(p.distal))) continue;
    const double y = p.distal >= 0 ? person(1, p.proximal) +
                                         p.ratio * (person(1, p.distal) - person(1, p.proximal))
                                   : person(1, p.proximal);
    sum += p.mass * y;
    mass += p.mass;
  }
  auto middle = [&](const std::vector<int>& pair, double* y) {
    if (pair.size() != 2 || !seen(pair[0]) || !seen(pair[1])) return false;
    *y = 0.5 * (person(1, pair[0]) + person(1, pair[1]));
    return true;
  };
  double top = 0, bottom = 0;
  if (middle(m.shoulders, &top) && middle(m.hips, &bottom)) {
    sum += 43.46 * (top + 0.4486 * (bottom - top));
    mass += 43.46;
  }
  double head = 0;
  int n = 0;
  for (const int j : m.head)
    if (seen(j)) {
      head += person(1, j);
      ++n;
    }
  if (n > 0) {
    sum += 6.94 * head / n;
    mass += 6.94;
  }
  return mass >= 0.8 * 100.0 ? sum / mass : kNaN;
}

double Percentile(std::vector<double> v, double p) {
  if (v.empty()) return kNaN;
  const size_t k = std::min(v.size() - 1, static_cast<size_t>(p * double(v.size() - 1) + 0.5));
  std::nth_element(v.begin(), v.begin() + static_cast<std::ptrdiff_t>(k), v.end());
  return v[k];
}

// The root of a t² + b t + c = 0 nearest `near` (NaN when none is real).
double RootNearest(double a, double b, double c, double near) {
  if (std::abs(a) < 1e-12) return std::abs(b) > 1e-12 ? -c / b : kNaN;
  const double disc = b * b - 4 * a * c;
  if (disc < 0) return kNaN;
  const double s = std::sqrt(disc);
  const double r1 = (-b - s) / (2 * a), r2 = (-b + s) / (2 * a);
  return std::abs(r1 - near) < std::abs(r2 - near) ? r1 : r2;
}

}  // namespace

BedLine RestLineOfBed(const BedDetection& bed) {
  const auto& c = bed.corners_px;  // clockwise from the top left: upper side c0–c1, lower c3–c2
  const Eigen::Vector2d left = 0.5 * (c[0] + c[3]), right = 0.5 * (c[1] + c[2]);
  const double width = std::abs(right.x() - left.x());
  const double height = 0.5 * ((c[3] - c[0]).norm() + (c[2] - c[1]).norm());
  if (!(width > height))
    throw InputError(bed.source,
                     "bed",
                     fmt::format("the bed is {:.0f} px wide and {:.0f} px high in the picture: a "
                                 "camera at its end or above it, whose rest line is not one line; "
                                 "film from beside the trampoline or give the line",
                                 width,
                                 height));
  BedLine line;
  line.slope = (right.y() - left.y()) / (right.x() - left.x());
  line.y0_px = left.y() - line.slope * left.x();
  line.source = "the bed detected in " + bed.source;
  return line;
}

bool ImageFlightOptions::IsValid(std::string* why) const {
  auto fail = [&](const char* w) {
    if (why) *why = w;
    return false;
  };
  if (!(min_confidence >= 0 && min_confidence <= 1))
    return fail("min_confidence must be in [0, 1]");
  if (!(clearance_fraction >= 0 && clearance_fraction < 0.5))
    return fail("clearance_fraction must be in [0, 0.5)");
  if (!(min_flight_s > 0 && std::isfinite(min_flight_s))) return fail("min_flight_s must be > 0");
  if (min_arc_frames < 3) return fail("min_arc_frames must be >= 3");
  return true;
}

int MostConfidentPerson(const std::vector<capture::DetectedPerson>& people, double min_confidence) {
  int best = -1;
  double best_sum = -1;
  for (size_t p = 0; p < people.size(); ++p) {
    const auto c = people[p].row(2).array();
    const double s = (c >= min_confidence).select(c, 0.0).sum();
    if (s > best_sum) {
      best_sum = s;
      best = static_cast<int>(p);
    }
  }
  return best;
}

double ImageFlights::TotalTimeOfFlight() const {
  double sum = 0;
  for (const ImageFlight& f : flights)
    if (!f.partial()) sum += f.time_of_flight_s();
  return sum;
}

namespace {

// The keypoints the flights are found from, per frame of the most confident person: each foot
// keypoint's position, the hips' mean height, the centre of mass's height and the head's top.
struct Tracks {
  Eigen::MatrixXd foot_x, foot_y;  // feet × frames
  Eigen::VectorXd head_top;
};

Tracks ReadTracks(const capture::KeypointDetections& detections,
                  const BodyParts& parts,
                  double c_min,
                  ImageFlights* out) {
  const int F = detections.num_frames();
  const MassModel mass_model = MakeMassModel(detections.names, parts.head);
  const Eigen::Index num_feet = static_cast<Eigen::Index>(parts.feet.size());
  Tracks t;
  t.foot_x = Eigen::MatrixXd::Constant(num_feet, F, kNaN);
  t.foot_y = Eigen::MatrixXd::Constant(num_feet, F, kNaN);
  t.head_top = Eigen::VectorXd::Constant(F, kNaN);
  for (int k = 0; k < F; ++k) {
    const auto& people = detections.frames[size_t(k)];
    if (people.empty()) continue;
    const int best = MostConfidentPerson(people, c_min);
    if (best < 0) continue;
    const capture::DetectedPerson& person = people[size_t(best)];
    auto seen = [&](int j) {
      return j < person.cols() && person(2, j) >= c_min && std::isfinite(person(1, j));
    };
    for (size_t i = 0; i < parts.feet.size(); ++i)
      if (seen(parts.feet[i])) {
        t.foot_x(Eigen::Index(i), k) = person(0, parts.feet[i]);
        t.foot_y(Eigen::Index(i), k) = person(1, parts.feet[i]);
      }
    double hip = 0;
    int hips = 0;
    for (int j : parts.hips)
      if (seen(j)) {
        hip += person(1, j);
        ++hips;
      }
    if (hips > 0) out->hip_y_px[k] = hip / hips;
    out->com_y_px[k] = CentreOfMassY(mass_model, person, c_min);
    for (int j : parts.head)
      if (seen(j))
        t.head_top[k] =
            std::min(std::isfinite(t.head_top[k]) ? t.head_top[k] : 1e300, person(1, j));
  }
  return t;
}

// The soles per frame: for each foot, the keypoint (heel, toe, ankle) lowest over the five frames
// around it, at its own position in the frame — a choice by the mean, so that the noise does not
// pick the lowest of several samples (which would put the soles ~σ low) — then the lower foot.
// Returns the head-to-soles distances of the frames that saw both.
std::vector<double> FindSoles(const BodyParts& parts, const Tracks& t, ImageFlights* out) {
  const int F = static_cast<int>(t.head_top.size());
  std::vector<double> heights;
  for (int k = 0; k < F; ++k) {
    double sole = -std::numeric_limits<double>::infinity(), x = kNaN;
    for (const std::vector<int>& group : parts.foot_groups) {
      int best = -1;
      double best_mean = -std::numeric_limits<double>::infinity();
      for (const int i : group) {
        if (!std::isfinite(t.foot_y(i, k))) continue;
        double sum = 0;
        int n = 0;
        for (int m = std::max(0, k - 2); m <= std::min(F - 1, k + 2); ++m)
          if (std::isfinite(t.foot_y(i, m))) {
            sum += t.foot_y(i, m);
            ++n;
          }
        if (sum / n > best_mean) {
          best_mean = sum / n;
          best = i;
        }
      }
      if (best >= 0 && t.foot_y(best, k) > sole) {
        sole = t.foot_y(best, k);
        x = t.foot_x(best, k);
      }
    }
    if (!std::isfinite(sole)) continue;
    out->sole_y_px[k] = sole;
    out->sole_x_px[k] = x;
    if (std::isfinite(t.head_top[k]) && sole > t.head_top[k])
      heights.push_back(sole - t.head_top[k]);
  }
  return heights;
}

// One flight's measurements from the soles' heights above the rest line and the centre of mass's
// arc in the picture.
class FlightMeasure {
 public:
  FlightMeasure(const ImageFlights& out,
                const Eigen::VectorXd& h,
                const ImageFlightOptions& options)
      : out_(out), h_(h), options_(options), dt_(1.0 / out.rate_hz), F_(int(h.size())) {}

  // The flight whose airborne run is frames a..b.
  ImageFlight Measure(int a, int b, std::vector<std::string>* warnings) {
    ImageFlight f;
    // The crossings: the last frame on the bed (h ≤ 0) before the run, the first after it.
    for (int k = a - 1; k >= 0; --k)
      if (std::isfinite(h_[k]) && h_[k] <= 0) {
        f.last_contact_frame = k;
        break;
      }
    for (int k = b + 1; k < F_; ++k)
      if (std::isfinite(h_[k]) && h_[k] <= 0) {
        f.first_contact_frame = k;
        break;
      }
    // The airborne frames between them (h > 0), and the centre of mass's arc over them.
    first_air_ = f.last_contact_frame >= 0 ? f.last_contact_frame + 1 : a;
    last_air_ = f.first_contact_frame >= 0 ? f.first_contact_frame - 1 : b;
    FitArc();
    f.com_accel_px_s2 = 2 * coef_[2];
    f.apex_s = std::isfinite(coef_[2]) ? t_mid_ - coef_[1] / (2 * coef_[2])
                                       : 0.5 * (first_air_ + last_air_) * dt_;
    // The airborne frame next to each crossing that saw the soles.
    int takeoff_off = f.last_contact_frame + 1, landing_off = f.first_contact_frame - 1;
    while (takeoff_off <= b && !std::isfinite(h_[takeoff_off])) ++takeoff_off;
    while (landing_off >= a && !std::isfinite(h_[landing_off])) --landing_off;
    f.takeoff_s = f.last_contact_frame >= 0
                      ? Crossing(f.last_contact_frame, takeoff_off, &f.takeoff_method)
                      : kNaN;
    f.landing_s = f.first_contact_frame >= 0
                      ? Crossing(f.first_contact_frame, landing_off, &f.landing_method)
                      : kNaN;
    WarnUnseen(warnings);
    if (f.first_contact_frame >= 0)
      f.landing_px = Eigen::Vector2d(out_.sole_x_px[f.first_contact_frame],
                                     out_.sole_y_px[f.first_contact_frame]);
    return f;
  }

 private:
  // The centre of mass's arc: y = c0 + c1 τ + c2 τ², τ = t − t_mid, over the airborne frames
  // (NaN when there are too few or it does not go up then down).
  void FitArc() {
    std::vector<int> arc;
    for (int k = first_air_; k <= last_air_; ++k)
      if (std::isfinite(out_.com_y_px[k]) && std::isfinite(h_[k]) && h_[k] > 0) arc.push_back(k);
    t_mid_ = 0.5 * (first_air_ + last_air_) * dt_;
    coef_ = Eigen::Vector3d::Constant(kNaN);
    if (static_cast<int>(arc.size()) < options_.min_arc_frames) return;
    Eigen::MatrixXd A(arc.size(), 3);
    Eigen::VectorXd y(arc.size());
    for (size_t i = 0; i < arc.size(); ++i) {
      const double tau = arc[i] * dt_ - t_mid_;
      A.row(Eigen::Index(i)) << 1, tau, tau * tau;
      y[Eigen::Index(i)] = out_.com_y_px[arc[i]];
    }
    coef_ = A.colPivHouseholderQr().solve(y);
    if (!(coef_[2] > 0)) coef_.setConstant(kNaN);  // not an arc going up then down
  }

  // The soles' crossing of the line between frame `on` (on the bed) and `off` (in the air), by
  // their linear interpolation; at high frame rates a straight line through the soles' heights in
  // every frame within 25 ms of that crossing (on either side of the line): the noise averaged
  // rather than the crossing moved to wherever it made the last frame dip below the line.
  double SolesCrossing(int on, int off) const {
    const double t_on = on * dt_, t_off = off * dt_;
    double soles = t_on + (t_off - t_on) * (-h_[on]) / (h_[off] - h_[on]);
    double sw = 0, st = 0, sh = 0, stt = 0, sth = 0;
    int n = 0;
    const int reach = static_cast<int>(std::ceil(0.025 / dt_)) + 1;
    for (int k = std::max(0, std::min(on, off) - reach);
         k <= std::min(F_ - 1, std::max(on, off) + reach);
         ++k) {
      if (!std::isfinite(h_[k]) || std::abs(k * dt_ - soles) > 0.025) continue;
      const double t = k * dt_ - soles;
      sw += 1;
      st += t;
      sh += h_[k];
      stt += t * t;
      sth += t * h_[k];
      ++n;
    }
    const double det = sw * stt - st * st;
    if (n > 2 && det > 0) {
      const double slope = (sw * sth - st * sh) / det, intercept = (sh - slope * st) / sw;
      if (std::abs(slope) > 0) {
        const double t = soles - intercept / slope;
        if (std::abs(t - soles) <= dt_) soles = t;
      }
    }
    return soles;
  }

  // One crossing: the soles', or, when the arc is there, the arc's with the soles' offset at `off`.
  double Crossing(int on, int off, std::string* method) const {
    const double soles = SolesCrossing(on, off);
    *method = "soles";
    if (!options_.time_from_arc || !std::isfinite(coef_[2])) return soles;
    // The soles' offset from the arc: their mean over the airborne frames within 50 ms of the
    // crossing (the legs still as they left the bed), `off` at least.
    const int step = off > on ? 1 : -1;
    double offset = 0;
    int n = 0;
    for (int k = off;
         k >= first_air_ && k <= last_air_ && (n == 0 || std::abs(k - off) * dt_ <= 0.05);
         k += step) {
      if (!std::isfinite(out_.sole_y_px[k])) continue;
      const double tau = k * dt_ - t_mid_;
      offset += out_.sole_y_px[k] - (coef_[0] + coef_[1] * tau + coef_[2] * tau * tau);
      ++n;
    }
    if (n == 0) return soles;
    offset /= n;
    const double rest = out_.bed.At(out_.sole_x_px[off]);
    // The arc plus the offset reaches the rest line: c2 τ² + c1 τ + (c0 + offset − rest) = 0.
    const double tau = RootNearest(coef_[2], coef_[1], coef_[0] + offset - rest, soles - t_mid_);
    const double t = t_mid_ + tau;
    // The arc's crossing is taken when it is within a frame of the soles' own, or within 20 ms
    // at high frame rates, where the noise moves the soles' last frame on the bed by several.
    if (!std::isfinite(t) || std::abs(t - soles) > std::max(dt_, 0.02)) return soles;
    *method = "arc";
    return t;
  }

  // The athlete not seen for a part of the flight (out of the picture, above it or beside it; or
  // hidden): its arc and apex rest on the frames around, and the user hears which flight.
  void WarnUnseen(std::vector<std::string>* warnings) const {
    int unseen = 0;
    for (int k = first_air_; k <= last_air_; ++k)
      unseen += !std::isfinite(out_.sole_y_px[k]) && !std::isfinite(out_.hip_y_px[k]);
    const int airborne = last_air_ - first_air_ + 1;
    if (airborne > 0 && unseen > 0.2 * airborne)
      warnings->push_back(fmt::format(
          "flight {} ({:.2f}–{:.2f} s): the athlete is not seen in {} of its {} frames in the "
          "air (out of the picture?): its height and shape rest on the frames around",
          out_.flights.size() + 1,
          first_air_ * dt_,
          last_air_ * dt_,
          unseen,
          airborne));
  }

  const ImageFlights& out_;
  const Eigen::VectorXd& h_;
  const ImageFlightOptions& options_;
  const double dt_;
  const int F_;
  int first_air_ = 0, last_air_ = 0;
  double t_mid_ = 0;
  Eigen::Vector3d coef_ = Eigen::Vector3d::Constant(kNaN);
};

// Per frame: 1 in the air (the soles above `clearance`), 0 on the bed (at or below the line), −1
// unknown (before anything is seen); in between, the state before.
std::vector<int> AirStates(const Eigen::VectorXd& h, double clearance) {
  std::vector<int> air(size_t(h.size()), -1);
  int state = -1;
  for (Eigen::Index k = 0; k < h.size(); ++k) {
    if (std::isfinite(h[k])) {
      if (h[k] > clearance)
        state = 1;
      else if (h[k] <= 0)
        state = 0;
      else if (state < 0)
        state = 0;
    }
    air[size_t(k)] = state;
  }
  return air;
}

}  // namespace

ImageFlights FindFlightsInImage(const capture::KeypointDetections& detections,
                                double rate_hz,
                                const BedLine& bed,
                                const ImageFlightOptions& options) {
  DemandValidOptions(options, "flights from the image");
  if (!(rate_hz > 0 && rate_hz <= 100000))
    throw InputError(detections.source,
                     "rate",
                     fmt::format("a frame rate of {:g} Hz is outside (0, 100000] Hz", rate_hz));
  const BodyParts parts = FindParts(detections.names);
  if (parts.hips.empty() || parts.feet.empty())
    throw InputError(
        detections.source,
        "detections",
        "the keypoints name no hips or no feet (ankles, heels, toes): the soles and the "
        "hips are what the flights are found from");
  const int F = detections.num_frames();
  ImageFlights out;
  out.bed = bed;
  out.rate_hz = rate_hz;
  out.sole_y_px.setConstant(F, kNaN);
  out.sole_x_px.setConstant(F, kNaN);
  out.hip_y_px.setConstant(F, kNaN);
  out.com_y_px.setConstant(F, kNaN);
  const Tracks tracks = ReadTracks(detections, parts, options.min_confidence, &out);
  const std::vector<double> heights = FindSoles(parts, tracks, &out);
  if (heights.size() < 5)
    throw InputError(
        detections.source,
        "detections",
        fmt::format("the athlete's head and feet are seen together in {} frame(s): too "
                    "few to tell the athlete's size in the picture (5 needed)",
                    heights.size()));
  // The extended body (upright or upside down, not tucked): a high percentile of the head–soles
  // distance.
  out.athlete_height_px = Percentile(heights, 0.9);
  const double clearance = options.clearance_fraction * out.athlete_height_px;

  // Height of the soles above the rest line (px, up positive) and the air/contact state.
  Eigen::VectorXd h(F);
  for (int k = 0; k < F; ++k)
    h[k] = std::isfinite(out.sole_y_px[k]) ? bed.At(out.sole_x_px[k]) - out.sole_y_px[k] : kNaN;
  const std::vector<int> air = AirStates(h, clearance);
  const int min_frames = std::max(
      2, static_cast<int>(std::min(double(F) + 1, std::ceil(options.min_flight_s * rate_hz))));
  FlightMeasure measure(out, h, options);
  for (int a = 0; a < F;) {
    if (air[size_t(a)] != 1) {
      ++a;
      continue;
    }
    int b = a;
    while (b + 1 < F && air[size_t(b) + 1] == 1) ++b;
    if (b - a + 1 >= min_frames) {
      std::vector<std::string> warnings;
      const ImageFlight f = measure.Measure(a, b, &warnings);
      out.warnings.insert(out.warnings.end(), warnings.begin(), warnings.end());
      out.flights.push_back(f);
    }
    a = b + 1;
  }
  if (out.flights.empty())
    out.warnings.push_back(fmt::format(
        "no flight: the soles never rose {:.0f} px ({:.0f} % of the athlete's {:.0f} px) above the "
        "bed's line ({}) for {:.2f} s",
        clearance,
        100 * options.clearance_fraction,
        out.athlete_height_px,
        bed.source,
        options.min_flight_s));
  return out;
}

}  // namespace acro::vision
