// The generated robustness campaign (issue "Rules, not examples"; docs/limits.md, "The campaign").
// Every reader × every defect class (mutations.h), and the commands' options, outputs and signals,
// made from the samples and run against the real acrolab binary, two at a time. Each case is held
// to the promises of docs/limits.md:
//   - no crash (no signal but the one the case sends), no hang (10 s), exit 0, 1 or 2 (130/143
//     after a signal), never an internal error;
//   - a refusal is one line of ours ("acrolab…") that names the culprit (the file, or the option),
//     with no raw control character anywhere in what the program printed;
//   - memory within a small multiple of the input: peak RSS ≤ 2.5 × the good file's run + 12 × the
//     input's bytes + 64 MB;
//   - nothing half-written: a refused or interrupted run leaves only its inputs, no run leaves a
//     temporary file; a library given to it passes SQLite's integrity check and, when the command
//     failed, holds what it held;
//   - no silent acceptance: a non-finite number or a declared count the content does not hold that
//     is read anyway comes with a warning.
// ACRO_CAMPAIGN=full runs every generated case (docs/testing.md); by default a stratified sample
// (every 12th case of each reader × class, at least one each). ACRO_CAMPAIGN_ONLY=SURFACE keeps one
// reader; ACRO_CAMPAIGN_REPORT=FILE writes the counts and failures as JSON.
#include <fcntl.h>
#include <signal.h>
#include <sys/mount.h>
#include <sys/resource.h>
#include <sys/stat.h>
#include <sys/sysmacros.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <atomic>
#include <cctype>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <functional>
#include <map>
#include <mutex>
#include <set>
#include <sstream>
#include <string>
#include <thread>
#include <vector>

#include <fmt/format.h>
#include <gtest/gtest.h>
#include <sqlite3.h>
#include <nlohmann/json.hpp>

#include "mutations.h"
#include "refdata.h"
#include "run_command.h"

extern char** environ;

namespace {

namespace fs = std::filesystem;
using acro::campaign::Defect;
using acro::campaign::Format;
using acro::campaign::Mutation;
using acro::campaign::Special;

constexpr double kTimeout_s = 10.0;

std::string ReadBytes(const fs::path& p) {
  std::ifstream in(p, std::ios::binary);
  return std::string(std::istreambuf_iterator<char>(in), {});
}

void WriteBytes(const fs::path& p, const std::string& bytes) {
  std::ofstream(p, std::ios::binary | std::ios::trunc) << bytes;
}

// ---- Running one command.

struct Run {
  int status = -1;  // exit status; 128 + signal when killed
  int signal = 0;
  bool timed_out = false;
  double seconds = 0;
  long max_rss_kb = 0;
  std::string err, out;
};

// The peak resident memory of `pid`'s own image (VmHWM of /proc/PID/status) once it runs `name`:
// the image's high-water mark, not the fork's (rusage's ru_maxrss keeps the parent's peak across
// exec). 0 before the exec.
long PeakKb(pid_t pid, const std::string& name) {
  std::ifstream status("/proc/" + std::to_string(pid) + "/status");
  std::string line;
  bool ours = false;
  long kb = 0;
  while (std::getline(status, line)) {
    if (line.rfind("Name:", 0) == 0) ours = line.find(name.substr(0, 15)) != std::string::npos;
    if (line.rfind("VmHWM:", 0) == 0) kb = std::atol(line.c_str() + 6);
  }
  return ours ? kb : 0;
}

// Runs argv[0] with the arguments in `dir`, stdin and stdout from and to nothing, stderr kept;
// killed (the whole process group) after kTimeout_s; `send` sent after `send_after_s` when set.
Run Spawn(const std::vector<std::string>& argv,
          const fs::path& dir,
          const fs::path& err_file,
          const std::vector<std::string>& env,
          int send = 0,
          double send_after_s = 0) {
  const fs::path out_file = fs::path(err_file).replace_extension(".out");
  const std::string image = fs::path(argv[0]).filename().string();
  std::vector<std::string> environment;
  for (char** e = environ; *e != nullptr; ++e) environment.emplace_back(*e);
  for (const std::string& e : env) environment.push_back(e);
  std::vector<char*> args, envp;
  for (const std::string& a : argv) args.push_back(const_cast<char*>(a.c_str()));
  args.push_back(nullptr);
  for (const std::string& e : environment) envp.push_back(const_cast<char*>(e.c_str()));
  envp.push_back(nullptr);
  const std::string dir_text = dir.string(), err_text = err_file.string(),
                    out_text = out_file.string();
  const auto start = std::chrono::steady_clock::now();
  const pid_t pid = ::fork();
  if (pid == 0) {
    ::setpgid(0, 0);
    if (::chdir(dir_text.c_str()) != 0) ::_exit(120);
    const int in = ::open("/dev/null", O_RDONLY);
    const int out = ::open(out_text.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
    const int err = ::open(err_text.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
    if (in < 0 || out < 0 || err < 0) ::_exit(121);
    ::dup2(in, 0);
    ::dup2(out, 1);
    ::dup2(err, 2);
#if !defined(__SANITIZE_ADDRESS__)
    const rlimit as{2000000000ull, 2000000000ull};  // 2 GB of address space, as the suite's runs
    ::setrlimit(RLIMIT_AS, &as);
#endif
    ::execve(args[0], args.data(), envp.data());
    ::_exit(122);
  }
  Run run;
  bool sent = false;
  int raw = 0;
  rusage usage{};
  long peak_kb = 0;
  for (;;) {
    peak_kb = std::max(peak_kb, PeakKb(pid, image));
    const pid_t done = ::wait4(pid, &raw, WNOHANG, &usage);
    const double t =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    if (done == pid) {
      run.seconds = t;
      break;
    }
    if (send != 0 && !sent && t >= send_after_s) {
      ::kill(pid, send);
      sent = true;
    }
    if (t > kTimeout_s) {
      run.timed_out = true;
      ::kill(-pid, SIGKILL);
      ::kill(pid, SIGKILL);
      ::wait4(pid, &raw, 0, &usage);
      run.seconds = t;
      break;
    }
    std::this_thread::sleep_for(std::chrono::milliseconds(t < 1 ? 1 : 5));
  }
  ::kill(-pid, SIGKILL);  // anything the command left running
  run.max_rss_kb = peak_kb;
  if (WIFEXITED(raw)) {
    run.status = WEXITSTATUS(raw);
  } else if (WIFSIGNALED(raw)) {
    run.signal = WTERMSIG(raw);
    run.status = 128 + run.signal;
  }
  run.err = ReadBytes(err_file);
  run.out = ReadBytes(out_file);
  fs::remove(out_file);
  return run;
}

using acro::testing::LastLine;

// ---- The surfaces: a reader, the good file it is given, and the commands that read it.

struct Surface {
  std::string name;  // "c3d"
  std::string file;  // the input's name in the case directory
  Format format;
  std::vector<std::vector<std::string>> commands;  // acrolab's words; {F} the input, {S} the seeds
  std::vector<Defect> defects;
  int variants = 30;  // per defect class
  // Set after construction:
  std::vector<std::string> culprits = {};  // a refusal names one of these (default: file)
  bool library_output = false;             // the command writes into lib.sqlite
  std::string models_file = {};            // the input is this file of the pose models
  std::string dir = {};                    // the input sits in this folder (detections)
  bool reader_helper = false;              // read by acro_campaign_reader, not acrolab
};

const std::vector<Defect> kAllFileDefects = {Defect::kTruncation,
                                             Defect::kBitFlip,
                                             Defect::kCounts,
                                             Defect::kNonFinite,
                                             Defect::kAbsurd,
                                             Defect::kUnits,
                                             Defect::kNames,
                                             Defect::kEncoding,
                                             Defect::kSpecial,
                                             Defect::kNesting,
                                             Defect::kHugeLine};
const std::vector<Defect> kBinaryDefects = {
    Defect::kTruncation, Defect::kBitFlip, Defect::kCounts, Defect::kSpecial, Defect::kHugeLine};

struct Case {
  int index = 0;
  const Surface* surface = nullptr;
  Defect defect = Defect::kTruncation;
  int variant = 0;
  int command = 0;
  std::string what;
  std::uint64_t salt =
      0;              // the mutation is made again from (surface, defect, variant, salt) when run
  Mutation mutation;  // filled only while the case runs (the campaign's own memory stays small:
                      // a child's peak RSS counts its parent's from before exec)
  // Option, output, signal and full-disk cases: the words themselves.
  std::vector<std::string> words;
  std::vector<std::string> culprits;
  int signal = 0;
  double signal_after_s = 0;
  bool full_disk = false;
  std::string baseline_key;
  bool declared_count = false;
};

struct Baseline {
  int status = 0;
  std::string last;
  long rss_kb = 0;
};

struct Verdict {
  std::string kind;  // "" when the case held every promise
  std::string detail;
};

class Campaign {
 public:
  Campaign(fs::path scratch, fs::path seeds)
      : scratch_(std::move(scratch)), seeds_(std::move(seeds)) {}

  void MakeSeeds();
  void MakeSurfaces();
  std::vector<Case> Generate();
  void Baselines();
  Verdict RunCase(const Case& c, int worker);

  const std::vector<Surface>& surfaces() const { return surfaces_; }
  bool full_disk_available() const { return !small_fs_.empty(); }
  void MountSmallFilesystem();
  void UnmountSmallFilesystem();

 private:
  std::vector<std::string> Words(const std::vector<std::string>& words,
                                 const fs::path& input) const;
  Verdict Judge(const Case& c,
                const Run& run,
                const fs::path& dir,
                const std::set<std::string>& inputs,
                std::size_t input_bytes,
                int library_trials_before) const;
  void PlaceInput(const Case& c,
                  const fs::path& dir,
                  std::set<std::string>* inputs,
                  std::size_t* bytes) const;

  fs::path scratch_, seeds_;
  fs::path small_fs_;
  std::vector<Surface> surfaces_;
  std::map<std::string, Baseline> baselines_;
};

fs::path Exe() {
  return fs::path(ACROLAB_EXE);
}

// Runs acrolab once to make a seed; the campaign cannot start without its seeds.
void MakeWith(const std::vector<std::string>& words, const fs::path& dir) {
  std::vector<std::string> argv = {Exe().string()};
  argv.insert(argv.end(), words.begin(), words.end());
  const Run run = Spawn(argv, dir, dir / "seed_stderr.txt", {});
  if (run.status != 0)
    throw std::runtime_error("making a seed failed: " + words[0] + ": " + run.err);
  fs::remove(dir / "seed_stderr.txt");
}

void Campaign::MakeSeeds() {
  const fs::path samples = acro::testing::SourceDir() / "samples";
  fs::create_directories(seeds_);
  fs::copy_file(samples / "trials/straight_jump/straight_jump.c3d", seeds_ / "trial.c3d");
  fs::copy_file(samples / "trials/trampoline_routine/side_camera.mp4", seeds_ / "video.mp4");
  fs::copy_file(samples / "trials/trampoline_routine/side_camera.toml", seeds_ / "calib.toml");
  fs::copy_file(samples / "athletes/sample_athlete.yaml", seeds_ / "athlete.yaml");
  fs::copy_file(samples / "athletes/sample_athlete_yeadon.yaml", seeds_ / "yeadon.yaml");
  {
    std::string skill = ReadBytes(samples / "skills/back_tuck.yaml");
    const std::string from = "athlete: ../athletes/sample_athlete.yaml";
    skill.replace(skill.find(from), from.size(), "athlete: " + (seeds_ / "athlete.yaml").string());
    WriteBytes(seeds_ / "skill.yaml", skill);
  }
  fs::copy_file(acro::testing::SourceDir() / "analysis/reconstruct/markersets/helen_hayes.yaml",
                seeds_ / "markerset.yaml");
  // An age group's rules with every section a club edits: requirements, zones, execution steps and
  // the synchronisation's conversion.
  WriteBytes(
      seeds_ / "rules.yaml",
      ReadBytes(acro::testing::SourceDir() / "rules/fig-wagc-13-16-first-routine.yaml") +
          "execution:\n  knees_bent: [[10, 0.1], [30, 0.2]]\n  late_opening: [[0.25, 0.1], [0.12, "
          "0.2]]\n"
          "synchronisation:\n  element_points: 2.0\n  points_lost_per_s: 8\n  tolerance_s: 0.002\n"
          "  source: a club's reading\n");
  MakeWith({"convert", "trial.c3d", "trial.trc"}, seeds_);
  MakeWith({"convert", "trial.c3d", "trial.csv"}, seeds_);
  MakeWith({"reconstruct", "trial.c3d", "--athlete", "athlete.yaml", "--quiet", "-o", "rec"},
           seeds_);
  fs::copy_file(seeds_ / "rec/trial.mot", seeds_ / "angles.mot");
  MakeWith({"library",
            "add",
            "--library",
            "library.sqlite",
            "--athlete",
            "athlete.yaml",
            "trial.c3d",
            "--quiet"},
           seeds_);
  WriteBytes(seeds_ / "routine.yaml",
             "name: campaign\nathlete: " + (seeds_ / "athlete.yaml").string() +
                 "\nskills:\n  - 40o\n  - code: 40<\n    flight_time_s: 1.5\n");
  WriteBytes(seeds_ / "jobs.txt",
             "trial.c3d --athlete athlete.yaml --session 2026-01-02 --notes 'first day'\n"
             "# a comment\ntrial.trc --athlete athlete.yaml --place hall\n");
  // The side camera in the other calibration formats, the same numbers.
  WriteBytes(
      seeds_ / "calib.yml",
      "%YAML:1.0\n---\nimage_width: 1920\nimage_height: 1080\ncamera_matrix: !!opencv-matrix\n"
      "   rows: 3\n   cols: 3\n   dt: d\n   data: [ 1482., 0., 968.4, 0., 1478.5, 536.1, 0., 0., "
      "1. ]\n"
      "distortion_coefficients: !!opencv-matrix\n   rows: 1\n   cols: 4\n   dt: d\n"
      "   data: [ -0.062, 0.018, 0.0004, -0.0003 ]\n"
      "rvec: !!opencv-matrix\n   rows: 3\n   cols: 1\n   dt: d\n   data: [ 1.5707963267948966, 0., "
      "0. ]\n"
      "tvec: !!opencv-matrix\n   rows: 3\n   cols: 1\n   dt: d\n   data: [ -0.4, 3.4, 9.7 ]\n");
  WriteBytes(seeds_ / "calib.json",
             "{\n\"image_width\": 1920,\n\"image_height\": 1080,\n\"camera_matrix\": {\"type_id\": "
             "\"opencv-matrix\", "
             "\"rows\": 3, \"cols\": 3, \"dt\": \"d\", \"data\": [1482.0, 0.0, 968.4, 0.0, 1478.5, "
             "536.1, 0.0, 0.0, 1.0]},\n"
             "\"distortion_coefficients\": {\"type_id\": \"opencv-matrix\", \"rows\": 1, \"cols\": "
             "4, \"dt\": \"d\", "
             "\"data\": [-0.062, 0.018, 0.0004, -0.0003]},\n"
             "\"rvec\": {\"type_id\": \"opencv-matrix\", \"rows\": 3, \"cols\": 1, \"dt\": \"d\", "
             "\"data\": [1.5707963267948966, 0.0, 0.0]},\n"
             "\"tvec\": {\"type_id\": \"opencv-matrix\", \"rows\": 3, \"cols\": 1, \"dt\": \"d\", "
             "\"data\": [-0.4, 3.4, 9.7]}\n}\n");
  // Qualisys: rotation rows r11…r33 of the camera in the lab (its axes x right, y up, z back),
  // position in mm, intrinsics in 1/64 px (docs/formats/calibration-qca.md).
  WriteBytes(
      seeds_ / "calib.qca",
      "<?xml version=\"1.0\"?>\n<calibration>\n <cameras>\n"
      "  <camera active=\"1\" serial=\"side\" model=\"Miqus\">\n"
      "   <fov_video left=\"0\" top=\"0\" right=\"1919\" bottom=\"1079\"/>\n"
      "   <transform x=\"400\" y=\"-9700\" z=\"3400\" r11=\"1\" r12=\"0\" r13=\"0\" r21=\"0\" "
      "r22=\"0\" "
      "r23=\"-1\" r31=\"0\" r32=\"1\" r33=\"0\"/>\n"
      "   <intrinsic focalLengthU=\"94848\" focalLengthV=\"94624\" centerPointU=\"61977.6\" "
      "centerPointV=\"34310.4\" radialDistortion1=\"-0.062\" radialDistortion2=\"0.018\" "
      "radialDistortion3=\"0\" tangentalDistortion1=\"0.0004\" tangentalDistortion2=\"-0.0003\"/>\n"
      "  </camera>\n </cameras>\n</calibration>\n");
  // OpenPose JSON detections of three frames (BODY_25B, one person).
  fs::create_directories(seeds_ / "det");
  for (int f = 0; f < 3; ++f) {
    nlohmann::json people = nlohmann::json::array();
    std::vector<double> k;
    for (int j = 0; j < 25; ++j) {
      k.push_back(900 + 10 * j + f);
      k.push_back(400 + 12 * j);
      k.push_back(0.9);
    }
    people.push_back({{"person_id", {-1}}, {"pose_keypoints_2d", k}});
    WriteBytes(seeds_ / "det" / fmt::format("side_{:012d}_keypoints.json", f),
               nlohmann::json({{"version", 1.3}, {"people", people}}).dump(1) + "\n");
  }
}

void Campaign::MakeSurfaces() {
  const std::string S = seeds_.string() + "/";
  auto text_defects = kAllFileDefects;
  surfaces_ = {
      {"c3d",
       "jump.c3d",
       Format::kC3d,
       {{"info", "{F}"}, {"convert", "{F}", "out.trc"}},
       kAllFileDefects,
       44},
      {"trc",
       "jump.trc",
       Format::kText,
       {{"info", "{F}"}, {"convert", "{F}", "out.c3d"}},
       text_defects,
       44},
      {"csv",
       "jump.csv",
       Format::kText,
       {{"info", "{F}"}, {"convert", "{F}", "out.trc"}},
       text_defects,
       34},
      {"storage", "angles.mot", Format::kText, {{"storage", "{F}"}}, text_defects, 28},
      {"athlete",
       "athlete.yaml",
       Format::kText,
       {{"body", "--profile", "{F}", "--json"}},
       text_defects,
       34},
      {"yeadon",
       "yeadon.yaml",
       Format::kText,
       {{"body", "--profile", "{F}", "--json"}},
       text_defects,
       28},
      {"skill",
       "skill.yaml",
       Format::kText,
       {{"optimize", "{F}", "-o", "out", "--model", "2", "--intervals", "10"}},
       text_defects,
       28},
      {"routine",
       "routine.yaml",
       Format::kText,
       {{"routine", "{F}", "-o", "out"}},
       text_defects,
       23},
      {"markerset",
       "markers.yaml",
       Format::kText,
       {{"reconstruct",
         S + "trial.c3d",
         "--markerset",
         "{F}",
         "--athlete",
         S + "athlete.yaml",
         "--quiet",
         "-o",
         "out"}},
       text_defects,
       16},
      {"toml",
       "calib.toml",
       Format::kText,
       {{"project", S + "trial.c3d", "--calib", "{F}", "--csv", "out.csv"}},
       text_defects,
       34},
      {"opencv-yml",
       "calib.yml",
       Format::kText,
       {{"project", S + "trial.c3d", "--calib", "{F}", "--csv", "out.csv"}},
       text_defects,
       34},
      {"opencv-json",
       "calib.json",
       Format::kJson,
       {{"project", S + "trial.c3d", "--calib", "{F}", "--csv", "out.csv"}},
       text_defects,
       28},
      {"qca",
       "calib.qca",
       Format::kXml,
       {{"project", S + "trial.c3d", "--calib", "{F}", "--csv", "out.csv"}},
       text_defects,
       28},
      {"detections",
       "side_000000000001_keypoints.json",
       Format::kJson,
       {{"overlay",
         "--detections",
         "det",
         "--video",
         S + "video.mp4",
         "--frames",
         "0:2",
         "-o",
         "out.mp4"}},
       text_defects,
       23},
      {"video",
       "clip.mp4",
       Format::kMp4,
       {{"video", "info", "{F}"}, {"video", "frame", "{F}", "--frame", "5", "-o", "f.png"}},
       kBinaryDefects,
       48},
      {"library",
       "lib.sqlite",
       Format::kSqlite,
       {{"library", "list", "--library", "{F}"},
        {"library",
         "add",
         "--library",
         "{F}",
         "--athlete",
         S + "athlete.yaml",
         S + "trial.trc",
         "--quiet"}},
       kBinaryDefects,
       36},
      {"batch",
       "jobs.txt",
       Format::kText,
       {{"batch", "{F}", "--library", "lib.sqlite", "--print-jobs"}},
       text_defects,
       23},
      {"rules",
       "rules.yaml",
       Format::kText,
       {{"synchro",
         S + "trial.c3d",
         S + "trial.c3d",
         "--athlete",
         S + "athlete.yaml",
         "--rules",
         "{F}",
         "-o",
         "out"}},
       text_defects,
       16},
      {"pose-model",
       "pose_landmark_lite.onnx",
       Format::kBinary,
       {{"detect", S + "video.mp4", "--model", "lite", "--frames", "0:1", "-o", "out", "--quiet"}},
       {Defect::kTruncation, Defect::kBitFlip, Defect::kSpecial, Defect::kHugeLine},
       8},
      {"pose-manifest",
       "MANIFEST",
       Format::kText,
       {{"detect", S + "video.mp4", "--model", "lite", "--frames", "0:1", "-o", "out", "--quiet"}},
       {Defect::kTruncation,
        Defect::kBitFlip,
        Defect::kNames,
        Defect::kEncoding,
        Defect::kSpecial,
        Defect::kHugeLine},
       6},
  };
  for (Surface& s : surfaces_) {
    if (s.name == "storage") s.reader_helper = true;
    if (s.name == "detections") {
      s.dir = "det";  // the input sits among the other frames' files
      s.culprits = {s.file, "det"};
    }
    if (s.name == "pose-model" || s.name == "pose-manifest") {
      s.models_file = s.file;
      s.culprits = {s.file, "pose model", "models"};
    }
  }
  for (Surface& s : surfaces_)
    if (s.name == "c3d")
      s.commands.push_back({"library",
                            "add",
                            "--library",
                            "lib.sqlite",
                            "--athlete",
                            S + "athlete.yaml",
                            "{F}",
                            "--quiet"});
}

std::string SeedFor(const Surface& s, const fs::path& seeds) {
  static const std::map<std::string, std::string> files = {
      {"c3d", "trial.c3d"},
      {"trc", "trial.trc"},
      {"csv", "trial.csv"},
      {"storage", "angles.mot"},
      {"athlete", "athlete.yaml"},
      {"yeadon", "yeadon.yaml"},
      {"skill", "skill.yaml"},
      {"routine", "routine.yaml"},
      {"markerset", "markerset.yaml"},
      {"toml", "calib.toml"},
      {"opencv-yml", "calib.yml"},
      {"opencv-json", "calib.json"},
      {"qca", "calib.qca"},
      {"detections", "det/side_000000000001_keypoints.json"},
      {"video", "video.mp4"},
      {"library", "library.sqlite"},
      {"batch", "jobs.txt"},
      {"rules", "rules.yaml"}};
  if (!s.models_file.empty()) {
    // The installed models (scripts/install-models.sh).
    return "";
  }
  return ReadBytes(seeds / files.at(s.name));
}

// The installed pose models' folder, as acrolab finds it (acro/pose/pose_models.h); empty when
// they are not installed.
fs::path InstalledModels() {
  fs::path root;
  if (const char* m = std::getenv("ACRO_MODELS"); m != nullptr && *m != '\0') {
    root = m;
  } else if (const char* c = std::getenv("XDG_CACHE_HOME"); c != nullptr && *c != '\0') {
    root = fs::path(c) / "acrolab/models";
  } else {
    root = fs::path(std::getenv("HOME") ? std::getenv("HOME") : ".") / ".cache/acrolab/models";
  }
  std::error_code ec;
  for (auto it = fs::directory_iterator(root, ec); !ec && it != fs::directory_iterator();
       it.increment(ec))
    if (it->path().filename().string().rfind("mediapipe-pose-", 0) == 0) return it->path();
  return {};
}

fs::path ModelsDir() {
  static const fs::path dir = InstalledModels();
  return dir;
}

std::vector<Case> Campaign::Generate() {
  std::vector<Case> cases;
  const char* only = std::getenv("ACRO_CAMPAIGN_ONLY");
  std::uint64_t salt = 1;
  const fs::path models = ModelsDir();
  for (const Surface& s : surfaces_) {
    ++salt;
    if (only != nullptr && *only != '\0' && s.name != only) continue;
    std::string seed;
    if (!s.models_file.empty()) {
      if (models.empty()) continue;
      seed = ReadBytes(models / s.models_file);
    } else {
      seed = SeedFor(s, seeds_);
    }
    for (Defect d : s.defects) {
      for (int v = 0; v < s.variants; ++v) {
        std::optional<Mutation> m = acro::campaign::Mutate(seed, s.format, d, v, salt, 16u << 20);
        if (!m) continue;
        Case c;
        c.surface = &s;
        c.defect = d;
        c.variant = v;
        c.command = v % static_cast<int>(s.commands.size());
        c.what = m->what;
        c.salt = salt;
        c.declared_count = m->declared_count;
        c.culprits = s.culprits.empty() ? std::vector<std::string>{s.file} : s.culprits;
        c.baseline_key = s.name + "/" + std::to_string(c.command);
        cases.push_back(std::move(c));
      }
    }
  }
  if (only != nullptr && *only != '\0' && std::string(only) != "commands") {
    for (size_t i = 0; i < cases.size(); ++i) cases[i].index = static_cast<int>(i);
    return cases;
  }
  // Every command × its number options: non-finite, absurd, empty, not a number.
  const std::string S = seeds_.string() + "/";
  struct Option {
    std::vector<std::string> command;  // with {V} for the value
    std::string option;
  };
  const std::vector<Option> options = {
      {{"reconstruct",
        S + "trial.c3d",
        "--athlete",
        S + "athlete.yaml",
        "--quiet",
        "-o",
        "out",
        "--cutoff",
        "{V}"},
       "--cutoff"},
      {{"reconstruct",
        S + "trial.c3d",
        "--athlete",
        S + "athlete.yaml",
        "--quiet",
        "-o",
        "out",
        "--max-gap",
        "{V}"},
       "--max-gap"},
      {{"reconstruct",
        S + "trial.c3d",
        "--athlete",
        S + "athlete.yaml",
        "--quiet",
        "-o",
        "out",
        "--window",
        "{V}"},
       "--window"},
      {{"reconstruct",
        S + "trial.c3d",
        "--height",
        "{V}",
        "--mass",
        "60",
        "--sex",
        "f",
        "--quiet",
        "-o",
        "out"},
       "--height"},
      {{"body", "--height", "1.7", "--mass", "{V}", "--sex", "m"}, "--mass"},
      {{"body", "--profile", S + "athlete.yaml", "--pose", "{V}"}, "--pose"},
      {{"project",
        S + "trial.c3d",
        "--calib",
        S + "calib.toml",
        "--video",
        S + "video.mp4",
        "--offset-s",
        "{V}",
        "--csv",
        "out.csv"},
       "--offset-s"},
      {{"project",
        S + "trial.c3d",
        "--calib",
        S + "calib.toml",
        "--video",
        S + "video.mp4",
        "--event",
        "{V}",
        "--csv",
        "out.csv"},
       "--event"},
      {{"project",
        S + "trial.c3d",
        "--calib",
        S + "calib.toml",
        "--rate",
        "{V}",
        "--csv",
        "out.csv"},
       "--rate"},
      {{"project",
        S + "trial.c3d",
        "--calib",
        S + "calib.toml",
        "--axes",
        "{V}",
        "--csv",
        "out.csv"},
       "--axes"},
      {{"sync",
        S + "trial.c3d",
        "--calib",
        S + "calib.toml",
        "--detections",
        "side=" + S + "det",
        "--fps",
        "{V}"},
       "--fps"},
      {{"sync",
        S + "trial.c3d",
        "--calib",
        S + "calib.toml",
        "--video",
        S + "video.mp4",
        "--search-s",
        "{V}"},
       "--search-s"},
      {{"video", "frame", S + "video.mp4", "--time", "{V}", "-o", "f.png"}, "--time"},
      {{"video", "frame", S + "video.mp4", "--frame", "{V}", "-o", "f.png"}, "--frame"},
      {{"design", "{V}", "--athlete", S + "athlete.yaml", "-o", "out", "--no-simulate"}, "CODE"},
      {{"design",
        "40o",
        "--athlete",
        S + "athlete.yaml",
        "-o",
        "out",
        "--no-simulate",
        "--flight-time",
        "{V}"},
       "--flight-time"},
      {{"routine", "--codes", "{V}", "--athlete", S + "athlete.yaml", "-o", "out"}, "--codes"},
      {{"routine",
        "--codes",
        "40o",
        "--athlete",
        S + "athlete.yaml",
        "-o",
        "out",
        "--marker-noise-mm",
        "{V}"},
       "--marker-noise-mm"},
      {{"synchro",
        S + "trial.c3d",
        S + "trial.c3d",
        "--athlete",
        S + "athlete.yaml",
        "--offset-s",
        "{V}",
        "-o",
        "out"},
       "--offset-s"},
      {{"detect", S + "video.mp4", "--model", "lite", "--frames", "{V}", "-o", "out", "--quiet"},
       "--frames"},
      {{"overlay",
        "--detections",
        S + "det",
        "--video",
        S + "video.mp4",
        "--frames",
        "{V}",
        "-o",
        "out.mp4"},
       "--frames"},
      {{"optimize", S + "skill.yaml", "-o", "out", "--intervals", "{V}"}, "--intervals"},
      {{"library", "query", "--library", S + "library.sqlite", "--tof-min", "{V}"}, "--tof-min"},
      {{"library", "query", "--library", S + "library.sqlite", "--from", "{V}"}, "--from"},
      {{"batch", S + "jobs.txt", "--library", "lib.sqlite", "--print-jobs", "--job", "{V}"},
       "--job"},
      {{"calibrate", "intrinsics", "--board", "{V}", "-o", "out.toml", S + "video.mp4"}, "--board"},
      {{"calibrate",
        "intrinsics",
        "--board",
        "checkerboard:4x7:60mm",
        "--video-step-s",
        "{V}",
        "-o",
        "out.toml",
        S + "video.mp4"},
       "--video-step-s"},
  };
  const std::vector<std::string> values = {"nan",
                                           "inf",
                                           "-inf",
                                           "-1",
                                           "0",
                                           "1e300",
                                           "-1e300",
                                           "abc",
                                           "",
                                           std::string(400, '9'),
                                           "1:0",
                                           "0:1e9",
                                           "\x1b[31mred",
                                           "1e-320"};
  for (const Option& o : options) {
    for (size_t k = 0; k < values.size(); ++k) {
      Case c;
      c.defect = Defect::kOption;
      c.variant = static_cast<int>(k);
      c.what = fmt::format(
          "{} '{}'", o.option, values[k].size() > 20 ? values[k].substr(0, 6) + "…" : values[k]);
      for (const std::string& w : o.command) c.words.push_back(w == "{V}" ? values[k] : w);
      c.culprits = {o.option, "'" + values[k].substr(0, 6)};
      if (o.option == "CODE" || o.option == "--codes") c.culprits.push_back(values[k].substr(0, 3));
      cases.push_back(std::move(c));
    }
  }
  // Outputs that cannot be written as asked, for every command that writes.
  const std::vector<std::vector<std::string>> writers = {
      {"convert", S + "trial.c3d", "{O}.trc"},
      {"project", S + "trial.c3d", "--calib", S + "calib.toml", "--csv", "{O}.csv"},
      {"video", "frame", S + "video.mp4", "--frame", "3", "-o", "{O}.png"},
      {"reconstruct", S + "trial.c3d", "--athlete", S + "athlete.yaml", "--quiet", "-o", "{O}"},
      {"overlay",
       "--detections",
       S + "det",
       "--video",
       S + "video.mp4",
       "--frames",
       "0:2",
       "-o",
       "{O}.mp4"},
      {"routine", "--codes", "40o", "--athlete", S + "athlete.yaml", "-o", "{O}"},
      {"body", "--profile", S + "athlete.yaml", "--mesh", "{O}.obj"},
      {"library", "export", "--library", S + "library.sqlite", "-o", "{O}.csv"},
  };
  const std::vector<std::pair<std::string, std::string>> outputs = {
      {"a path under a missing folder", "no/such/folder/out"},
      {"a path under a regular file", "file.txt/out"},
      {"a name of 300 bytes", std::string(300, 'n')},
      {"a path of 5000 bytes", "d/" + std::string(4990, 'p')},
      {"a name with terminal escapes", "\x1b[31mout"},
  };
  for (const auto& w : writers) {
    for (const auto& [what, out] : outputs) {
      Case c;
      c.defect = Defect::kOutput;
      c.what = w[0] + " to " + what;
      for (std::string word : w) {
        if (size_t at = word.find("{O}"); at != std::string::npos) word.replace(at, 3, out);
        c.words.push_back(word);
      }
      c.culprits = {out.substr(0, 8), "out", "folder"};
      cases.push_back(std::move(c));
    }
    if (!small_fs_.empty()) {
      Case c;
      c.defect = Defect::kFullDisk;
      c.what = w[0] + " to a full filesystem";
      for (std::string word : w) {
        if (size_t at = word.find("{O}"); at != std::string::npos)
          word.replace(at, 3, (small_fs_ / "out").string());
        c.words.push_back(word);
      }
      c.full_disk = true;
      c.culprits = {small_fs_.string(), "space"};
      cases.push_back(std::move(c));
    }
  }
  // Signals at random instants in commands that write.
  std::mt19937_64 rng(42);
  for (int k = 0; k < 40; ++k) {
    Case c;
    c.defect = Defect::kSignal;
    const auto& w = writers[static_cast<size_t>(k) % writers.size()];
    for (std::string word : w) {
      if (size_t at = word.find("{O}"); at != std::string::npos) word.replace(at, 3, "out");
      c.words.push_back(word);
    }
    c.signal = k % 2 ? SIGTERM : SIGINT;
    c.signal_after_s = 0.05 + static_cast<double>(rng() % 1000) / 1000.0;
    c.what = fmt::format("{} interrupted by {} after {:.3f} s",
                         w[0],
                         k % 2 ? "SIGTERM" : "SIGINT",
                         c.signal_after_s);
    cases.push_back(std::move(c));
  }
  for (size_t i = 0; i < cases.size(); ++i) cases[i].index = static_cast<int>(i);
  return cases;
}

std::vector<std::string> Campaign::Words(const std::vector<std::string>& words,
                                         const fs::path& input) const {
  std::vector<std::string> out;
  for (std::string w : words) {
    if (w == "{F}") w = input.string();
    out.push_back(w);
  }
  return out;
}

void Campaign::PlaceInput(const Case& c,
                          const fs::path& dir,
                          std::set<std::string>* inputs,
                          std::size_t* bytes) const {
  const Surface& s = *c.surface;
  fs::path target;
  if (!s.models_file.empty()) {
    const fs::path models = dir / "models" / ModelsDir().filename();
    fs::create_directories(models);
    for (const fs::directory_entry& e : fs::directory_iterator(ModelsDir()))
      if (e.path().filename() != s.models_file)
        fs::create_symlink(e.path(), models / e.path().filename());
    target = models / s.models_file;
    inputs->insert("models");
  } else if (!s.dir.empty()) {
    fs::create_directories(dir / s.dir);
    for (const fs::directory_entry& e : fs::directory_iterator(seeds_ / s.dir))
      if (e.path().filename() != s.file) fs::copy_file(e.path(), dir / s.dir / e.path().filename());
    target = dir / s.dir / s.file;
    inputs->insert(s.dir);
  } else {
    target = dir / s.file;
    inputs->insert(s.file);
  }
  const Mutation& m = c.mutation;
  *bytes = m.bytes.size();
  switch (m.special) {
    case Special::kNone:
    case Special::kEmpty:
    case Special::kOneByte:
      WriteBytes(target, m.bytes);
      break;
    case Special::kDirectory:
      fs::create_directories(target);
      break;
    case Special::kFifo:
      ::mkfifo(target.c_str(), 0644);
      break;
    case Special::kLinkLoop:
      fs::create_symlink(target.filename(), target);
      break;
    case Special::kDanglingLink:
      fs::create_symlink("no_such_file", target);
      break;
    case Special::kZeroDevice:
      if (::mknod(target.c_str(), S_IFCHR | 0644, makedev(1, 5)) != 0)
        fs::create_symlink("/dev/zero", target);
      break;
  }
  if (s.name == "c3d" && c.command == 2) {
    fs::copy_file(seeds_ / "library.sqlite", dir / "lib.sqlite");
    inputs->insert("lib.sqlite");
  }
}

int TrialsIn(const fs::path& library) {
  sqlite3* db = nullptr;
  int count = -1;
  if (sqlite3_open_v2(library.c_str(), &db, SQLITE_OPEN_READONLY, nullptr) == SQLITE_OK) {
    sqlite3_stmt* st = nullptr;
    if (sqlite3_prepare_v2(db, "SELECT count(*) FROM trials", -1, &st, nullptr) == SQLITE_OK &&
        sqlite3_step(st) == SQLITE_ROW)
      count = sqlite3_column_int(st, 0);
    sqlite3_finalize(st);
  }
  sqlite3_close(db);
  return count;
}

bool Intact(const fs::path& library) {
  sqlite3* db = nullptr;
  bool ok = false;
  if (sqlite3_open_v2(library.c_str(), &db, SQLITE_OPEN_READONLY, nullptr) == SQLITE_OK) {
    sqlite3_stmt* st = nullptr;
    if (sqlite3_prepare_v2(db, "PRAGMA integrity_check", -1, &st, nullptr) == SQLITE_OK &&
        sqlite3_step(st) == SQLITE_ROW)
      ok = std::string(reinterpret_cast<const char*>(sqlite3_column_text(st, 0))) == "ok";
    sqlite3_finalize(st);
  }
  sqlite3_close(db);
  return ok;
}

std::string Printable(const std::string& s) {
  std::string out;
  for (unsigned char c : s)
    out += (c < 0x20 || c == 0x7f) ? fmt::format("\\x{:02x}", c)
                                   : std::string(1, static_cast<char>(c));
  return out.size() > 400 ? out.substr(0, 400) + "…" : out;
}

Verdict Campaign::Judge(const Case& c,
                        const Run& run,
                        const fs::path& dir,
                        const std::set<std::string>& inputs,
                        std::size_t input_bytes,
                        int library_trials_before) const {
  const std::string last = LastLine(run.err);
  if (run.timed_out) return {"hang", fmt::format("still running after {:.0f} s", kTimeout_s)};
  if (run.signal != 0 && run.signal != c.signal)
    return {"crash", fmt::format("signal {}: {}", run.signal, Printable(last))};
  const bool interrupted = c.signal != 0 && (run.status == 130 || run.status == 143);
  if (run.status == 3 || run.err.find("internal error") != std::string::npos)
    return {"internal error", Printable(last)};
  if (!(run.status == 0 || run.status == 1 || run.status == 2 || interrupted))
    return {"exit status", fmt::format("{}: {}", run.status, Printable(last))};
  for (unsigned char ch : run.err)
    if ((ch < 0x20 && ch != '\n' && ch != '\t') || ch == 0x7f)
      return {"raw control byte", fmt::format("byte {:02x} in: {}", ch, Printable(last))};
  if (run.status == 1 || run.status == 2) {
    if (last.rfind("acrolab", 0) != 0) return {"not our line", Printable(last)};
    bool named = false;
    for (const std::string& culprit : c.culprits)
      if (!culprit.empty() && last.find(Printable(culprit).substr(0, 40)) != std::string::npos)
        named = true;
    const auto base = baselines_.find(c.baseline_key);
    const bool as_baseline = base != baselines_.end() && base->second.last == last;
    if (!named && !as_baseline) return {"culprit not named", Printable(last)};
  }
  // Memory: within a small multiple of the good run and the input.
  if (const auto base = baselines_.find(c.baseline_key); base != baselines_.end()) {
    const double bound_kb = 2.5 * static_cast<double>(base->second.rss_kb) +
                            12.0 * static_cast<double>(input_bytes) / 1024.0 + 65536.0;
    if (static_cast<double>(run.max_rss_kb) > bound_kb)
      return {"memory",
              fmt::format("{} MB > {} MB (good file {} MB, input {} MB)",
                          run.max_rss_kb / 1024,
                          static_cast<long>(bound_kb / 1024),
                          base->second.rss_kb / 1024,
                          input_bytes >> 20)};
  } else if (run.max_rss_kb > 1500 * 1024) {
    return {"memory", fmt::format("{} MB", run.max_rss_kb / 1024)};
  }
  // Silent acceptance: a declared count the content does not hold, or a number that is not finite,
  // read on without a warning (on stdout, as `info` lists them, or stderr). NaN is the trial and
  // storage formats' own notation for a missing value (TRC, CSV, OpenSim's .mot): read as a gap.
  const bool nan_is_gap =
      (c.what.find("= nan") != std::string::npos || c.what.find("= NaN") != std::string::npos) &&
      c.surface != nullptr &&
      (c.surface->name == "trc" || c.surface->name == "csv" || c.surface->name == "storage");
  const bool must_warn = c.declared_count || (c.defect == Defect::kNonFinite && !nan_is_gap);
  auto warned = [&] {
    for (const std::string* text : {&run.err, &run.out}) {
      std::string lower = *text;
      std::transform(lower.begin(), lower.end(), lower.begin(), [](unsigned char ch) {
        return std::tolower(ch);
      });
      if (lower.find("warning") != std::string::npos &&
          lower.find("warnings    0") == std::string::npos)
        return true;
    }
    return false;
  };
  if (must_warn && run.status == 0 && !warned()) return {"silent acceptance", c.what};
  // Leftovers: a temporary file anywhere; after a refusal or an interruption, anything new.
  std::vector<std::string> left;
  std::error_code ec;
  for (auto it =
           fs::recursive_directory_iterator(dir, fs::directory_options::skip_permission_denied, ec);
       !ec && it != fs::recursive_directory_iterator();
       it.increment(ec)) {
    const std::string name = it->path().filename().string();
    // Lexical: a link loop among the inputs must not be resolved to be named.
    const std::string top = it->path().lexically_relative(dir).begin()->string();
    if (inputs.count(top)) {
      if (it->is_directory(ec) && !it->is_symlink(ec)) it.disable_recursion_pending();
      continue;
    }
    if (name.find(".tmp") != std::string::npos || name.find(".partial") != std::string::npos)
      left.push_back(name);
    else if (run.status != 0 && it.depth() == 0 && top != "stderr.txt")
      left.push_back(name);
    if (it->is_symlink(ec)) it.disable_recursion_pending();
  }
  if (c.full_disk && fs::exists(small_fs_, ec)) {
    for (const fs::directory_entry& e : fs::directory_iterator(small_fs_, ec))
      if (e.path().filename() != "filler" && e.path().filename() != "lost+found")
        left.push_back(e.path().string());
  }
  // An interrupt that comes after outputs were moved into place keeps them, whole, and says how
  // many
  // (", N finished kept"): those may stay; anything more is half-written.
  size_t kept = 0;
  if (const size_t at = run.err.find(" finished kept"); c.signal != 0 && at != std::string::npos) {
    size_t from = run.err.rfind(", ", at);
    if (from != std::string::npos)
      kept = static_cast<size_t>(std::atoi(run.err.c_str() + from + 2));
  }
  size_t temporaries = 0;
  for (const std::string& name : left)
    if (name.find(".tmp") != std::string::npos || name.find(".partial") != std::string::npos)
      ++temporaries;
  if (temporaries > 0 || left.size() > kept)
    return {"half-written",
            fmt::format("left {} after exit {}", Printable(left.front()), run.status)};
  // The library: whole, and unchanged by a failure.
  const fs::path library = dir / "lib.sqlite";
  if (library_trials_before >= 0 && fs::is_regular_file(library, ec)) {
    if (!Intact(library)) return {"library damaged", "integrity_check failed"};
    if (run.status != 0 && TrialsIn(library) != library_trials_before)
      return {
          "library changed",
          fmt::format(
              "{} trials after a failure, {} before", TrialsIn(library), library_trials_before)};
  }
  return {};
}

Verdict Campaign::RunCase(const Case& c, int worker) {
  const fs::path dir = scratch_ / fmt::format("case_{}", worker);
  std::error_code ec;
  fs::remove_all(dir, ec);
  fs::create_directories(dir);
  std::set<std::string> inputs;
  std::size_t bytes = 0;
  std::vector<std::string> argv, env = {"ACROLAB_LIBRARY_WAIT_S=2"};
  if (c.surface != nullptr) {
    Case made = c;
    const std::string seed = c.surface->models_file.empty()
                                 ? SeedFor(*c.surface, seeds_)
                                 : ReadBytes(ModelsDir() / c.surface->models_file);
    made.mutation =
        *acro::campaign::Mutate(seed, c.surface->format, c.defect, c.variant, c.salt, 16u << 20);
    PlaceInput(made, dir, &inputs, &bytes);
    const Surface& s = *c.surface;
    const fs::path input = s.dir.empty() ? fs::path(s.file) : fs::path(s.dir);
    if (s.reader_helper) {
      argv = {ACRO_CAMPAIGN_READER};
    } else {
      argv = {Exe().string()};
    }
    for (const std::string& w :
         Words(s.commands[static_cast<size_t>(c.command)], s.dir.empty() ? input : fs::path()))
      argv.push_back(w);
    if (!s.models_file.empty()) env.push_back("ACRO_MODELS=" + (dir / "models").string());
    if (s.name == "library" || (s.name == "c3d" && c.command == 2)) {
      // The mutated library is its own input; the c3d's add writes into a good copy.
    }
  } else {
    argv = {Exe().string()};
    argv.insert(argv.end(), c.words.begin(), c.words.end());
    WriteBytes(dir / "file.txt", "a file, not a folder\n");
    inputs.insert("file.txt");
  }
  const int before = fs::is_regular_file(dir / "lib.sqlite", ec) &&
                             (c.surface == nullptr || c.surface->name != "library")
                         ? TrialsIn(dir / "lib.sqlite")
                         : -1;
  const Run run = Spawn(
      argv, dir, scratch_ / fmt::format("stderr_{}.txt", worker), env, c.signal, c.signal_after_s);
  Verdict v = Judge(c, run, dir, inputs, bytes, before);
  if (c.full_disk) {
    for (const fs::directory_entry& e : fs::directory_iterator(small_fs_, ec))
      if (e.path().filename() != "filler" && e.path().filename() != "lost+found")
        fs::remove_all(e.path(), ec);
  }
  fs::remove_all(dir, ec);
  return v;
}

void Campaign::Baselines() {
  for (const Surface& s : surfaces_) {
    if (!s.models_file.empty() && ModelsDir().empty()) continue;
    for (size_t k = 0; k < s.commands.size(); ++k) {
      Case c;
      c.surface = &s;
      c.command = static_cast<int>(k);
      c.mutation.bytes =
          s.models_file.empty() ? SeedFor(s, seeds_) : ReadBytes(ModelsDir() / s.models_file);
      const fs::path dir = scratch_ / "baseline";
      std::error_code ec;
      fs::remove_all(dir, ec);
      fs::create_directories(dir);
      std::set<std::string> inputs;
      std::size_t bytes = 0;
      PlaceInput(c, dir, &inputs, &bytes);
      std::vector<std::string> argv = {s.reader_helper ? std::string(ACRO_CAMPAIGN_READER)
                                                       : Exe().string()};
      for (const std::string& w :
           Words(s.commands[k], s.dir.empty() ? fs::path(s.file) : fs::path()))
        argv.push_back(w);
      std::vector<std::string> env = {"ACROLAB_LIBRARY_WAIT_S=2"};
      if (!s.models_file.empty()) env.push_back("ACRO_MODELS=" + (dir / "models").string());
      const Run run = Spawn(argv, dir, scratch_ / "baseline_stderr.txt", env);
      EXPECT_EQ(run.status, 0) << s.name << " command " << k << " on the good file: " << run.err;
      baselines_[s.name + "/" + std::to_string(k)] = {
          run.status, LastLine(run.err), run.max_rss_kb};
      std::printf("baseline %-14s %-10s exit %d, %.2f s, %ld MB\n",
                  s.name.c_str(),
                  s.commands[k][0].c_str(),
                  run.status,
                  run.seconds,
                  run.max_rss_kb / 1024);
      fs::remove_all(dir, ec);
    }
  }
}

// A 1 MB tmpfs of the campaign's own, filled to the last byte, for the full-disk cases (needs the
// right to mount: root in CI's container; otherwise the class is skipped and said).
void Campaign::MountSmallFilesystem() {
  const fs::path point = scratch_ / "small_fs";
  fs::create_directories(point);
  if (::mount("tmpfs", point.c_str(), "tmpfs", 0, "size=1m") != 0) {
    std::printf("full disk: cannot mount a small tmpfs here (%s): class skipped\n",
                std::strerror(errno));
    return;
  }
  std::ofstream filler(point / "filler", std::ios::binary);
  const std::string block(4096, 'f');
  while (filler.write(block.data(), static_cast<std::streamsize>(block.size()))) filler.flush();
  small_fs_ = point;
}

void Campaign::UnmountSmallFilesystem() {
  if (!small_fs_.empty()) ::umount(small_fs_.c_str());
}

// Keeps every n-th case of each reader × class (at least one of each).
std::vector<Case> Sample(const std::vector<Case>& all, int every) {
  std::map<std::string, std::vector<const Case*>> groups;
  for (const Case& c : all)
    groups[(c.surface ? c.surface->name : "commands") + "/" + acro::campaign::DefectName(c.defect)]
        .push_back(&c);
  std::vector<Case> out;
  for (const auto& [key, cases] : groups)
    for (size_t k = 0; k < cases.size(); k += static_cast<size_t>(every)) out.push_back(*cases[k]);
  return out;
}

TEST(Campaign, EveryReaderAndCommandHoldsItsPromises) {
  const fs::path scratch = acro::testing::ScratchDir("campaign");
  Campaign campaign(scratch, scratch / "seeds");
  campaign.MakeSeeds();
  campaign.MakeSurfaces();
  campaign.MountSmallFilesystem();
  campaign.Baselines();
  if (::testing::Test::HasFailure()) {
    campaign.UnmountSmallFilesystem();
    return;
  }
  const std::vector<Case> all = campaign.Generate();
  const char* mode = std::getenv("ACRO_CAMPAIGN");
  const bool full = mode != nullptr && std::string(mode) == "full";
  const std::vector<Case> cases = full ? all : Sample(all, 12);
  std::printf(
      "campaign: %zu cases generated, %zu run (%s)\n",
      all.size(),
      cases.size(),
      full ? "ACRO_CAMPAIGN=full" : "the suite's sample: every 12th of each reader × class");

  struct Result {
    const Case* c;
    Verdict v;
    double seconds;
  };
  std::vector<Result> results(cases.size());
  std::atomic<size_t> next{0};
  const auto start = std::chrono::steady_clock::now();
  std::mutex print;
  auto worker = [&](int id) {
    for (size_t i; (i = next++) < cases.size();) {
      const auto t0 = std::chrono::steady_clock::now();
      results[i] = {&cases[i],
                    campaign.RunCase(cases[i], id),
                    std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count()};
      if (full && i % 250 == 0) {
        std::lock_guard<std::mutex> lock(print);
        std::printf("campaign: %zu / %zu\n", i, cases.size());
        std::fflush(stdout);
      }
    }
  };
  std::thread a(worker, 0), b(worker, 1);
  a.join();
  b.join();
  campaign.UnmountSmallFilesystem();
  const double seconds =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();

  // Counts by reader × class, and the failures.
  std::map<std::string, std::pair<int, int>> by_class, by_surface;
  std::map<std::string, int> by_kind;
  nlohmann::json failures = nlohmann::json::array();
  for (const Result& r : results) {
    const std::string cls = acro::campaign::DefectName(r.c->defect);
    const std::string surface = r.c->surface ? r.c->surface->name : "commands";
    ++by_class[cls].first;
    ++by_surface[surface].first;
    if (r.v.kind.empty()) continue;
    ++by_class[cls].second;
    ++by_surface[surface].second;
    ++by_kind[r.v.kind];
    failures.push_back({{"surface", surface},
                        {"class", cls},
                        {"case", Printable(r.c->what)},
                        {"command",
                         r.c->surface ? r.c->surface->commands[static_cast<size_t>(r.c->command)][0]
                                      : r.c->words[0]},
                        {"kind", r.v.kind},
                        {"detail", r.v.detail}});
  }
  std::printf("\n%-16s %7s %7s\n", "class", "cases", "failed");
  for (const auto& [k, v] : by_class) std::printf("%-16s %7d %7d\n", k.c_str(), v.first, v.second);
  std::printf("\n%-16s %7s %7s\n", "reader", "cases", "failed");
  for (const auto& [k, v] : by_surface)
    std::printf("%-16s %7d %7d\n", k.c_str(), v.first, v.second);
  std::printf("\n%zu cases in %.0f s (2 at a time); failures by kind:", cases.size(), seconds);
  for (const auto& [k, n] : by_kind) std::printf(" %s %d;", k.c_str(), n);
  std::printf("%s\n", by_kind.empty() ? " none" : "");
  for (size_t k = 0; k < failures.size() && k < 60; ++k)
    std::printf("FAIL %s\n", failures[k].dump().c_str());
  if (const char* report = std::getenv("ACRO_CAMPAIGN_REPORT");
      report != nullptr && *report != '\0') {
    nlohmann::json j = {{"cases_generated", all.size()},
                        {"cases_run", cases.size()},
                        {"seconds", seconds},
                        {"failures", failures}};
    for (const auto& [k, v] : by_class)
      j["by_class"][k] = {{"cases", v.first}, {"failed", v.second}};
    for (const auto& [k, v] : by_surface)
      j["by_reader"][k] = {{"cases", v.first}, {"failed", v.second}};
    std::ofstream(report) << j.dump(1) << "\n";
  }
  const char* only = std::getenv("ACRO_CAMPAIGN_ONLY");
  if (only == nullptr || *only == '\0') {
    EXPECT_GE(all.size(), 5000u) << "the campaign generates at least 5000 cases";
  }
  EXPECT_EQ(failures.size(), 0u);
}

}  // namespace
