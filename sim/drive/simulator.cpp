#include "slamprep/sim/drive/simulator.hpp"

#include <btBulletDynamicsCommon.h>

#include <algorithm>
#include <cassert>
#include <cmath>
#include <memory>
#include <sstream>

#include "slamprep/core/error.hpp"
#include "slamprep/core/freed_memory.hpp"
#include "slamprep/core/gyro_odometry.hpp"
#include "slamprep/core/odometry.hpp"
#include "slamprep/core/paths.hpp"
#include "slamprep/core/se2_cos_sin.hpp"
#include "slamprep/sim/drive/controller.hpp"
#include "slamprep/sim/drive/explore.hpp"
#include "slamprep/sim/drive/fault_injection.hpp"
#include "slamprep/sim/drive/floor_slip.hpp"
#include "slamprep/sim/drive/held_robot.hpp"
#include "slamprep/sim/drive/people.hpp"
#include "slamprep/sim/drive/rng.hpp"
#include "slamprep/sim/drive/sensors.hpp"
#include "slamprep/sim/physics/lidar.hpp"
#include "slamprep/sim/physics/robot.hpp"

namespace slamprep::sim {
namespace {

using StepState = MotionState;

/// The true state between two steps: pose by geodesic interpolation (constant twist over the
/// step), everything else linearly; acceleration is the step's mean.
struct Interval {
  const StepState& a;
  const StepState& b;

  double fraction(double t_s) const {
    return b.t_s > a.t_s ? (t_s - a.t_s) / (b.t_s - a.t_s) : 1.0;
  }
  SE2 pose(double t_s) const { return interpolate(a.T_world_base, b.T_world_base, fraction(t_s)); }
  Eigen::Vector2d wheelAngles(double t_s) const {
    const double f = fraction(t_s);
    return a.wheel_angle_rad + f * (b.wheel_angle_rad - a.wheel_angle_rad);
  }
  double yawRate(double t_s) const {
    const double f = fraction(t_s);
    return a.yaw_rate_radps + f * (b.yaw_rate_radps - a.yaw_rate_radps);
  }
  Eigen::Vector2d accelWorld() const {
    return b.t_s > a.t_s ? Eigen::Vector2d((b.v_world_mps - a.v_world_mps) / (b.t_s - a.t_s))
                         : Eigen::Vector2d::Zero();
  }
};

// ---- How the robot moves -----------------------------------------------------------------------

class Motion {
 public:
  virtual ~Motion() = default;
  virtual StepState initial() const = 0;
  /// Advances from prev to t_s (one physics step) and returns the new true state.
  virtual StepState step(const StepState& prev, double t_s) = 0;
  /// Why the last state cannot be trusted (the robot tipped over, the physics diverged), or "".
  virtual std::string problem() const { return ""; }
};

/// Bullet: the controller's wheel-rate targets go to the motors; the joints give the encoders.
/// A step that starts inside a held window runs with the chassis held (Robot::setHeld). With a
/// closed-loop segment the motion also drives the reference: the commands' kinematic replay with
/// the TRUE geometry (as KinematicMotion and the path check drive them), which the controller
/// compares with the true pose.
class PhysicsMotion : public Motion {
 public:
  PhysicsMotion(Scene& scene, const Controller& controller, const RobotConfig& config,
                const SE2& T_world_start, FloorSlip* slip, const HeldSchedule& held)
      : scene_(scene),
        controller_(controller),
        robot_(scene, config, T_world_start),
        slip_(slip),
        held_(held),
        true_geometry_(config.geometry),
        T_world_reference_(T_world_start) {
    angle0_ = {robot_.wheelAngleLeft(), robot_.wheelAngleRight()};
  }
  StepState initial() const override { return read(0.0); }
  std::string problem() const override {
    constexpr double kMaxTilt_rad = 0.5;  // ~30 deg: a diff-drive robot is on its side by then
    const SE2 T = robot_.T_world_base();
    if (!std::isfinite(T.x) || !std::isfinite(T.y) || !std::isfinite(T.yaw)) {
      return "the physics diverged (non-finite pose): raise physics_rate_hz";
    }
    if (robot_.tilt_rad() > kMaxTilt_rad) {
      return "the robot tipped over (tilt " + std::to_string(robot_.tilt_rad()) +
             " rad): lower the scenario's speeds or acceleration limits, or raise physics_rate_hz";
    }
    return "";
  }
  StepState step(const StepState& prev, double t_s) override {
    const Eigen::Vector2d target = targetRates(prev, t_s);
    robot_.setWheelRateTargets(target.x(), target.y());
    robot_.setHeld(held_.heldAt(prev.t_s));
    if (slip_) {
      const auto friction = slip_->update(prev.t_s, prev.T_world_base);
      robot_.setWheelFriction(friction[0], friction[1]);
    }
    scene_.step(t_s - prev.t_s);
    robot_.update();
    return read(t_s);
  }

 private:
  /// The open-loop command at the step's end, or the closed loop's from the error at its start.
  Eigen::Vector2d targetRates(const StepState& prev, double t_s) {
    if (!controller_.closedLoop()) return controller_.wheelRates(t_s);
    const Eigen::Vector2d target =
        controller_.wheelRates(t_s, prev.T_world_base, T_world_reference_);
    T_world_reference_ =
        T_world_reference_ * held_.bodyIncrement(controller_, true_geometry_, prev.t_s, t_s);
    return target;
  }

  StepState read(double t_s) const {
    StepState s;
    s.t_s = t_s;
    s.T_world_base = robot_.T_world_base();
    s.wheel_angle_rad =
        Eigen::Vector2d(robot_.wheelAngleLeft(), robot_.wheelAngleRight()) - angle0_;
    s.v_world_mps = robot_.linearVelocity_world();
    s.yaw_rate_radps = robot_.yawRate();
    return s;
  }

  Scene& scene_;
  const Controller& controller_;
  Robot robot_;
  FloorSlip* slip_;  // null: the floor is uniform
  const HeldSchedule& held_;
  DiffDriveParams true_geometry_;
  SE2 T_world_reference_;  ///< where the kinematic replay of the commands is (closed loop)
  Eigen::Vector2d angle0_ = Eigen::Vector2d::Zero();
};

/// A recorded run's states again, step for step (RecordedMotion): the sensors read the same
/// truth without the physics being stepped.
class ReplayedMotion : public Motion {
 public:
  explicit ReplayedMotion(const std::vector<StepState>& states) : states_(states) {}
  StepState initial() const override { return states_.front(); }
  StepState step(const StepState&, double t_s) override {
    const StepState& s = states_.at(++next_);
    assert(s.t_s == t_s);
    (void)t_s;
    return s;
  }

 private:
  const std::vector<StepState>& states_;
  std::size_t next_ = 0;
};

/// No physics: the wheels turn exactly as commanded and the base follows the exact arc of the
/// TRUE geometry over each step (core/odometry.hpp wheelIncrement), except while it is held.
class KinematicMotion : public Motion {
 public:
  KinematicMotion(const Controller& controller, const DiffDriveParams& true_geometry,
                  const SE2& T_world_start, const HeldSchedule& held)
      : controller_(controller), geometry_(true_geometry), start_(T_world_start), held_(held) {}
  StepState initial() const override {
    StepState s;
    s.T_world_base = start_;
    return s;
  }
  StepState step(const StepState& prev, double t_s) override {
    const Eigen::Vector2d dphi = controller_.wheelAngleIncrement(prev.t_s, t_s);
    StepState s;
    s.t_s = t_s;
    s.wheel_angle_rad = prev.wheel_angle_rad + dphi;
    s.T_world_base = prev.T_world_base * held_.bodyIncrement(controller_, geometry_, prev.t_s, t_s);
    const Eigen::Vector2d rates = controller_.wheelRates(t_s);
    const Eigen::Vector2d twist =
        held_.heldAt(t_s) ? Eigen::Vector2d::Zero() : geometry_.twist(rates.x(), rates.y());
    s.v_world_mps = s.T_world_base.rotation() * Eigen::Vector2d(twist.x(), 0.0);
    s.yaw_rate_radps = twist.y();
    return s;
  }

 private:
  const Controller& controller_;
  DiffDriveParams geometry_;
  SE2 start_;
  const HeldSchedule& held_;
};

// ---- Sensors, streamed step by step ---------------------------------------------------------

/// The rotating lidar: every beam whose time falls into a step is cast from the pose
/// interpolated to that time; the ground-truth undistorted point uses the measured range.
class LidarStream {
 public:
  LidarStream(const LidarConfig& config, std::uint64_t seed, ScanReadJitter read_jitter,
              People people, std::vector<Transient> transients, std::vector<ScanRecord>& out)
      : lidar_(config, seed),
        people_(std::move(people)),
        transients_(std::move(transients)),
        T_base_lidar_(SE2CosSin::from(config.T_base_lidar)),
        read_jitter_(read_jitter),
        out_(out) {
    const LaserScan header = lidar_.header(0.0);
    for (std::size_t i = 0; i < header.size(); ++i) {
      const double angle = header.beamAngle(i);  // as LaserScan::point computes it
      beam_dir_.emplace_back(std::cos(angle), std::sin(angle));
    }
    startScan();
  }

  /// Casts all beams with t_prev < t <= min(t_cur, t_end) (t = 0 included on the first call).
  /// Base pose at beam time t: T_a exp(f log(T_a^-1 T_b)), f = (t - t_a) / (t_b - t_a): the
  /// geodesic (constant twist) between the two steps, as core/se2.hpp interpolate().
  void advance(const Scene& scene, const Interval& step, double t_end_s) {
    const double t_limit = std::min(step.b.t_s, t_end_s);
    double t = nextTime();
    if (t > t_limit) return;
    const SE2CosSin T_a = SE2CosSin::from(step.a.T_world_base);
    const Eigen::Vector3d xi = between(step.a.T_world_base, step.b.T_world_base).log();
    for (; t <= t_limit; t = nextTime()) {
      const SE2CosSin T_world_base = T_a * SE2CosSin::exp(step.fraction(t) * xi);
      castBeam(scene, T_world_base);
    }
  }

 private:
  double nextTime() const { return current_.scan.beamTime(beam_); }

  /// Scan k is stamped k / rate and taken where its revolution starts (a free-running head's
  /// boundary nearest the stamp, else the stamp) plus read_jitter_ (0 unless that fault is on).
  void startScan() {
    current_ = ScanRecord{};
    stamp_s_ = static_cast<double>(scan_index_) / lidar_.config().rate_hz;
    current_.scan =
        lidar_.header(stamp_s_ + lidar_.revolutionOffset(stamp_s_) + read_jitter_.next());
    current_.p_ref_true.assign(current_.scan.size(), std::nullopt);
    beam_ = 0;
  }

  void castBeam(const Scene& scene, const SE2CosSin& T_world_base) {
    const SE2CosSin T_world_lidar = T_world_base * T_base_lidar_;
    if (beam_ == 0) {
      T_lidar0_world_ = T_world_lidar.inverse();
      current_.T_world_base_true = T_world_base.se2();
    }
    const Eigen::Vector2d dir_world = T_world_lidar.rotate(beam_dir_[beam_]);
    const Eigen::Vector2d origin_world(T_world_lidar.x, T_world_lidar.y);
    const double range_m = measureBeam(scene, origin_world, dir_world, T_world_base);
    current_.scan.ranges_m[beam_] = range_m;
    if (std::isfinite(range_m)) {
      const Eigen::Vector2d p_lidar = range_m * beam_dir_[beam_];
      // p_ref = T_W_L(t_stamp)^-1 * T_W_L(t_i) * p_L_i
      // (docs/design.md#what-the-simulators-truth-means)
      current_.p_ref_true[beam_] = T_lidar0_world_ * (T_world_lidar * p_lidar);
    }
    if (++beam_ == current_.scan.size()) {
      current_.scan.stamp_s = stamp_s_;
      out_.push_back(std::move(current_));
      ++scan_index_;
      startScan();
    }
  }

  /// The beam's range: the world's, or what moves (people, the world's transients) where nearer;
  /// a return from a transient is marked so that the dropped-beam fault leaves it.
  double measureBeam(const Scene& scene, const Eigen::Vector2d& origin, const Eigen::Vector2d& dir,
                     const SE2CosSin& T_world_base) {
    const double t = nextTime(), max_m = lidar_.config().range_max_m;
    const auto person = people_.castRay(origin, dir, {T_world_base.x, T_world_base.y}, t, max_m);
    const auto transient = transients_.castRay(origin, dir, t, max_m);
    const auto moving = person && transient ? std::min(person, transient)
                        : person            ? person
                                            : transient;
    const Lidar::Beam beam = lidar_.measure(scene, origin, dir, beam_, moving);
    if (transient && beam.true_range_m == *transient && std::isfinite(beam.range_m))
      current_.replayed_beams.push_back(beam_);
    return beam.range_m;
  }

  Lidar lidar_;
  People people_;
  TransientCaster transients_;
  SE2CosSin T_base_lidar_;
  ScanReadJitter read_jitter_;
  std::vector<Eigen::Vector2d> beam_dir_;  ///< (cos, sin) of every beam angle
  std::vector<ScanRecord>& out_;
  std::int64_t scan_index_ = 0;
  double stamp_s_ = 0.0;  ///< the current scan's stamp, on the grid
  ScanRecord current_;
  std::size_t beam_ = 0;
  SE2CosSin T_lidar0_world_;
};

/// The encoders: the wheel angles at every sample time, counted through the random slip when
/// it is on (a sample step's turning times (1 + s), its turn times (1 + u)), then quantised to
/// ticks.
class EncoderStream {
 public:
  EncoderStream(const EncoderConfig& config, std::uint64_t seed, EncoderLog& out)
      : ticks_(config.ticks_per_revolution),
        clock_(config.rate_hz),
        slip_(config.slip_sigma, config.slip_tau_s, seed, config.turn_slip_sigma,
              config.common_slip_sigma),
        out_(out) {}

  void advance(const Interval& step, double t_end_s) {
    const double t_limit = std::min(step.b.t_s, t_end_s);
    for (double t = clock_.next_s(); t <= t_limit; clock_.advance(), t = clock_.next_s()) {
      const Eigen::Vector2d angle = counted(t, step.wheelAngles(t));
      out_.push_back({t, quantizeTicks(angle.x(), ticks_), quantizeTicks(angle.y(), ticks_)});
    }
  }

 private:
  Eigen::Vector2d counted(double t_s, const Eigen::Vector2d& angle_rad) {
    if (!slip_.on()) return angle_rad;
    const Eigen::Vector2d turned = angle_rad - previous_rad_;
    const double dt = out_.empty() ? 0.0 : t_s - out_.back().stamp_s;
    previous_rad_ = angle_rad;
    return slip_.count(turned, dt);
  }

  int ticks_;
  SampleClock clock_;
  WheelSlip slip_;
  Eigen::Vector2d previous_rad_ = Eigen::Vector2d::Zero();
  EncoderLog& out_;
};

class ImuStream {
 public:
  ImuStream(const ImuConfig& config, std::uint64_t seed, ImuLog& out)
      : imu_(config, seed), clock_(config.rate_hz), out_(out) {}

  void advance(const Interval& step, double t_end_s) {
    const double t_limit = std::min(step.b.t_s, t_end_s);
    for (double t = clock_.next_s(); t <= t_limit; clock_.advance(), t = clock_.next_s()) {
      // Horizontal specific force in the base frame (gravity is vertical): R^T a_world.
      const Eigen::Vector2d accel_base = step.pose(t).rotation().transpose() * step.accelWorld();
      out_.push_back(imu_.sample(t, step.yawRate(t), accel_base));
    }
  }

 private:
  Imu imu_;
  SampleClock clock_;
  ImuLog& out_;
};

/// The sensors, each sampling the steps as they come into the dataset's logs.
class SensorStreams {
 public:
  SensorStreams(const SimConfig& config, const Scene& scene, Dataset& data)
      : scene_(scene),
        lidar_(config.lidar, streamSeed(config.seed, RngStream::lidar),
               ScanReadJitter(config.faults, config.seed, config.lidar.rate_hz),
               People(config.people, streamSeed(config.seed, RngStream::people)),
               scene.world().transients, data.scans),
        encoders_(config.encoders, streamSeed(config.seed, RngStream::encoder_slip), data.encoders),
        imu_(config.imu, streamSeed(config.seed, RngStream::imu), data.imu) {}

  void sense(const Interval& step, double duration_s) {
    encoders_.advance(step, duration_s);
    imu_.advance(step, duration_s);
    lidar_.advance(scene_, step, duration_s);
  }

 private:
  const Scene& scene_;
  LidarStream lidar_;
  EncoderStream encoders_;
  ImuStream imu_;
};

/// What the dataset records about how it was made (docs/dataset.md).
DatasetInfo simulatedDatasetInfo(const SimConfig& config) {
  DatasetInfo info;
  info.world = config.world;
  info.scenario = config.scenario;
  info.seed = config.seed;
  info.true_geometry = config.robot.geometry;
  info.nominal_geometry = config.nominalGeometry();
  info.T_base_lidar = config.nominalMount();
  if (config.nominal.mountToldWrong()) info.true_T_base_lidar = config.lidar.T_base_lidar;
  info.ticks_per_revolution = config.encoders.ticks_per_revolution;
  info.config = toJson(config);
  info.config["encoders_from"] = "ticks";  // docs/dataset.md: simulated encoders count ticks
  // docs/dataset.md: the odometry's heading is the gyro's (absent: the wheels', as before).
  if (config.odometry.heading_from == OdometryHeading::gyro)
    info.config["odometry_heading"] = "gyro";
  return info;
}

/// The floor patches' wheel friction, when that fault is on (Bullet only).
std::optional<FloorSlip> floorSlipFor(const SimConfig& config, const World& world) {
  std::optional<FloorSlip> slip;
  if (config.faults.enable.has(Fault::floor_patches) && config.mode == SimMode::physics)
    slip.emplace(world.floor_patches, config.robot.wheel_friction,
                 config.robot.geometry.wheel_base_m / 2);
  return slip;
}

std::unique_ptr<Motion> makeMotion(const SimConfig& config, Scene& scene,
                                   const Controller& controller, const SE2& T_world_start,
                                   FloorSlip* slip, const HeldSchedule& held) {
  if (config.mode == SimMode::physics)
    return std::make_unique<PhysicsMotion>(scene, controller, config.robot, T_world_start, slip,
                                           held);
  return std::make_unique<KinematicMotion>(controller, config.robot.geometry, T_world_start, held);
}

std::int64_t physicsStepCount(const SimConfig& config, double duration_s) {
  return static_cast<std::int64_t>(std::ceil(duration_s * config.physics_rate_hz - 1e-9));
}

/// Bytes of the logs a run fills; the scans' ranges and true points are most of them.
std::size_t outputBytes(const SimConfig& config, double duration_s) {
  const double beams = duration_s * config.lidar.rate_hz * config.lidar.beams_per_revolution;
  const double poses = duration_s * (config.physics_rate_hz + config.encoders.rate_hz);
  return static_cast<std::size_t>(
      beams * (sizeof(double) + sizeof(std::optional<Eigen::Vector2d>)) +
      poses * sizeof(Stamped<SE2>) + duration_s * config.encoders.rate_hz * sizeof(EncoderSample) +
      duration_s * config.imu.rate_hz * sizeof(ImuSample));
}

/// Every output's length is known: reserve it, so the logs are not copied while they grow. In a
/// process's first run their memory is fresh: on huge pages it takes 512x fewer page faults.
void reserveOutputs(const SimConfig& config, double duration_s, Dataset& data) {
  // Capped: a day-long run's logs are gigabytes, and its faults are not what it waits for.
  constexpr std::size_t kMaxHugePageBytes = std::size_t{256} << 20;
  backNextAllocationsWithHugePages(std::min(outputBytes(config, duration_s), kMaxHugePageBytes));
  data.groundtruth.reserve(static_cast<std::size_t>(physicsStepCount(config, duration_s)) + 1);
  data.encoders.reserve(static_cast<std::size_t>(duration_s * config.encoders.rate_hz) + 2);
  data.imu.reserve(static_cast<std::size_t>(duration_s * config.imu.rate_hz) + 2);
  data.scans.reserve(static_cast<std::size_t>(duration_s * config.lidar.rate_hz) + 2);
}

/// Throws, naming the scenario segment, when the motion's state cannot be trusted.
void requireTrustworthyState(const Motion& motion, const Scenario& scenario, double t_s) {
  const std::string problem = motion.problem();
  if (problem.empty()) return;
  const ProfileSegment* segment = scenario.profile.segmentAt(t_s);
  std::ostringstream what;
  what << "at t = " << t_s << " s " << problem;
  throw InputError(segment != nullptr ? segment->where : scenario.source.string(), what.str());
}

/// Steps the motion from t = 0 to the end of the run, sensing every step; the ground truth
/// holds the pose at every step.
void runSteps(const SimConfig& config, const Scenario& scenario, double duration_s,
              const ProgressCallback& progress, Motion& motion, SensorStreams& sensors,
              PoseSeries& groundtruth, std::vector<StepState>* record) {
  const std::int64_t steps = physicsStepCount(config, duration_s);
  StepState prev = motion.initial();
  if (record) {
    record->reserve(static_cast<std::size_t>(steps) + 1);
    record->push_back(prev);
  }
  groundtruth.push_back(prev.t_s, prev.T_world_base);
  sensors.sense(Interval{prev, prev}, duration_s);  // samples at t = 0
  const std::int64_t report_every = std::max<std::int64_t>(1, steps / 200);
  for (std::int64_t n = 1; n <= steps; ++n) {
    const StepState cur = motion.step(prev, static_cast<double>(n) / config.physics_rate_hz);
    requireTrustworthyState(motion, scenario, cur.t_s);
    if (record) record->push_back(cur);
    groundtruth.push_back(cur.t_s, cur.T_world_base);
    sensors.sense(Interval{prev, cur}, duration_s);
    prev = cur;
    if (progress && (n % report_every == 0 || n == steps))
      progress(std::min(cur.t_s, duration_s), duration_s);
  }
}

/// Drops the scans the odometry does not cover, so that readDataset accepts the dataset.
void dropScansOutsideEncoders(Dataset& data) {
  // A scan completed after the last encoder sample (its last beam inside the final encoder
  // period) is not covered by the odometry: readDataset would refuse it, so it is not kept.
  while (!data.scans.empty() && !data.encoders.empty() &&
         data.scans.back().scan.endTime() > data.encoders.back().stamp_s)
    data.scans.pop_back();
  // Stamp jitter can put the first scan's first beam before the first (jittered) encoder
  // sample; such a scan is not covered either.
  while (!data.scans.empty() && !data.encoders.empty() &&
         data.scans.front().scan.stamp_s < data.encoders.front().stamp_s)
    data.scans.erase(data.scans.begin());
}

/// The odometry the robot publishes: heading from the wheels, or from the integrated gyro.
PoseSeries publishedOdometry(const SimConfig& config, const Dataset& data) {
  const DatasetInfo& info = data.info;
  return config.odometry.heading_from == OdometryHeading::gyro
             ? integrateEncodersGyroHeading(data.encoders, data.imu, info.nominal_geometry,
                                            info.ticks_per_revolution)
             : integrateEncoders(data.encoders, info.nominal_geometry, info.ticks_per_revolution);
}

}  // namespace

SimResult simulate(const SimConfig& config, const ProgressCallback& progress) {
  validate(config, "config");
  const World world = loadWorld(resolveDataPath(config.world));
  const Scenario scenario = loadScenario(resolveDataPath(config.scenario));
  return simulate(config, world, scenario, progress);
}

namespace {

/// The simulation; `recorded` (null: none) is replayed where its key is this configuration's,
/// else filled.
SimResult run(const SimConfig& config, const World& world, const Scenario& written,
              const ProgressCallback& progress, ScenePhysicsParams physics,
              RecordedMotion* recorded) {
  validate(config, "config");
  const double duration_s =
      config.duration_s > 0.0 ? config.duration_s : written.profile.duration_s();
  checkRunSize(config, duration_s);
  if (config.solver_iterations > 0) physics.solver_iterations = config.solver_iterations;
  Scene scene(worldWithFaults(world, config.faults.enable), physics);
  const SE2 T_world_start = config.startPose(world.T_world_start);
  const Scenario scenario = planExplore(scene, written, config, T_world_start);
  const HeldSchedule held = config.faults.enable.has(Fault::held_robot)
                                ? HeldSchedule(config.faults, config.seed, duration_s)
                                : HeldSchedule();
  checkPathInWorld(scene, scenario, config, T_world_start, duration_s, held);

  Dataset data;
  data.info = simulatedDatasetInfo(config);
  const Controller controller(scenario.profile, data.info.nominal_geometry);
  std::optional<FloorSlip> slip = floorSlipFor(config, world);
  FloorSlip* const slip_or_null = slip ? &*slip : nullptr;
  const std::string key = recorded && !slip ? motionKey(config) : std::string();
  const bool replay = !key.empty() && recorded->key == key && !recorded->states.empty();
  const std::unique_ptr<Motion> motion =
      replay ? std::make_unique<ReplayedMotion>(recorded->states)
             : makeMotion(config, scene, controller, T_world_start, slip_or_null, held);
  SensorStreams sensors(config, scene, data);
  reserveOutputs(config, duration_s, data);
  std::vector<StepState> states;
  const bool record = !key.empty() && !replay;
  runSteps(config, scenario, duration_s, progress, *motion, sensors, data.groundtruth,
           record ? &states : nullptr);
  if (record) *recorded = {key, std::move(states)};

  if (config.faults.enable.any())
    data.info.faults = injectFaults(config, world, slip_or_null, held, duration_s, data);
  dropScansOutsideEncoders(data);
  data.odom_nominal = publishedOdometry(config, data);
  for (ScanRecord& record : data.scans) {
    record.T_odom_base_nominal = data.odom_nominal.at(record.scan.stamp_s);
  }
  SimResult result{std::move(data), {}};
  result.summary = summarize(result.dataset, config.mode);
  return result;
}

}  // namespace

SimResult simulate(const SimConfig& config, const World& world, const Scenario& scenario,
                   const ProgressCallback& progress, ScenePhysicsParams physics) {
  return run(config, world, scenario, progress, physics, nullptr);
}

SimResult simulate(const SimConfig& config, const World& world, const Scenario& scenario,
                   RecordedMotion& motion, const ProgressCallback& progress,
                   ScenePhysicsParams physics) {
  return run(config, world, scenario, progress, physics, &motion);
}

std::string motionKey(const SimConfig& config) {
  nlohmann::json j = toJson(config, true);
  for (const char* sensor : {"lidar", "encoders", "imu", "odometry"}) j.erase(sensor);
  // Of the faults, only a held body moves the robot otherwise (floor patches: never replayed).
  const nlohmann::json held = j["faults"]["held_robot"];
  j["faults"] = {{"held_robot", config.faults.enable.has(Fault::held_robot)},
                 {"held_robot_params", held}};
  return j.dump();
}

}  // namespace slamprep::sim
