#pragma once

#include <cstdint>
#include <map>
#include <set>
#include <string>
#include <vector>

#include "fleetnav/core/angles.hpp"
#include "fleetnav/core/robot_model.hpp"
#include "fleetnav/core/sensor_frame.hpp"
#include "fleetnav/sim/geometry2d.hpp"
#include "fleetnav/sim/noise.hpp"
#include "fleetnav/sim/world_description.hpp"

namespace fleetnav::sim {

constexpr double kDegToRad = kPi / 180.0;

/// Ultrasonic range sensor (Lely thesis ch. 3): a cone of rays; the nearest echo counts.
struct UltrasonicParams {
  double cone_rad = 10.0 * kDegToRad;
  int rays = 5;
  double min_range_m = 0.27;
  double max_range_m = 2.5;
  double noise_stddev_m = 0.01;
  /// A ray meeting a surface more obliquely than this (to the normal) returns no echo.
  double max_incidence_rad = 40.0 * kDegToRad;
  double dropout_probability = 0.01;  ///< per reading
};

/// 2D laser scanner (defaults: the KUKA platform's SICK S300, 270° at 0.5°).
struct LaserParams {
  double fov_rad = 270.0 * kDegToRad;
  int beams = 541;
  double min_range_m = 0.05;
  double max_range_m = 20.0;
  double noise_stddev_m = 0.01;
  double rate_hz = 10.0;
};

struct GpsParams {
  double stddev_m = 0.3;
  double rate_hz = 5.0;
};

/// Parameters of every exteroceptive sensor; the laser per robot kind.
struct ExteroceptiveParams {
  UltrasonicParams ultrasonic;
  LaserParams omni_laser;  ///< KUKA platform: 270° at 0.5°, 20 m
  LaserParams ackermann_laser{180.0 * kDegToRad, 361, 0.05, 30.0, 0.01, 10.0};  ///< capstone
  GpsParams gps;
  double charger_reach_m = 0.05;  ///< contact when the contact point is this close to the pole
  /// Inductive sensors measure where a stripe crosses their lateral line within ± this range
  /// (the thesis's sensor reads the stripe's lateral position), with this noise.
  double inductive_range_m = 0.15;
  double inductive_noise_m = 0.003;
  /// A stripe meeting the lateral line at less than this angle (a marker crossed at right
  /// angles to the travel) gives no lateral reading.
  double inductive_min_crossing_rad = 30.0 * kDegToRad;
  double bumper_margin_m = 0.02;  ///< the bumper fires this far out of the footprint
};

/// What the exteroceptive sensors sense, rebuilt by the simulation when the world or the
/// robots move: solids (statics with owner -1, robot footprints with their index), the floor
/// stripes and markers as strips, the charging poles and the regions hidden from ultrasonics.
struct SensingScene {
  std::vector<Shape2> statics;
  std::vector<Shape2> robots;
  struct Strip {
    Eigen::Vector2d a, b;
    double half_width_m;
    bool follow = true;  ///< a stripe to follow (markers are only crossed)
  };
  std::vector<Strip> strips;
  std::vector<Shape2> charging_poles;
  std::vector<FaultSpec> ultrasonic_hidden;
};

/// The static part of a scene from a world (statics, strips, poles).
SensingScene StaticScene(const WorldDescription& world);

/// Ultrasonics, inductive stripe sensors, lasers, charger contact, bumper and GPS of one robot,
/// placed per its RobotModel mounts, each sensor on its own seeded noise stream
/// (NoiseSeed(seed, robot_id, sensor name)). Not thread-safe.
class ExteroceptiveSensors {
 public:
  ExteroceptiveSensors(const RobotModel& model, ExteroceptiveParams params,
                       uint64_t simulation_seed, const std::string& robot_id);

  /// Fills the frame's ultrasonic, inductive, lasers (on laser ticks), charger contact, bumper
  /// and gps (on GPS ticks) for robot `robot_index` at `pose`. Sensors named in `dropped` (or
  /// all, when it holds "") report nothing: no echo, no detection, max-range scans, no fix.
  void Sample(const SensingScene& scene, int robot_index, const Pose2& pose, uint64_t tick,
              double period_s, const std::set<std::string>& dropped, SensorFrame* frame);

  const ExteroceptiveParams& params() const { return params_; }

 private:
  struct Hit {
    double distance_m;
    Eigen::Vector2d normal;
    bool found;
  };
  Hit Cast(const SensingScene& scene, const std::vector<const Shape2*>& candidates,
           const Eigen::Vector2d& origin, const Eigen::Vector2d& direction, double max_m) const;
  std::vector<const Shape2*> Candidates(const SensingScene& scene, int robot_index,
                                        const Eigen::Vector2d& origin, double reach_m,
                                        double z_m) const;
  NoiseStream& Stream(const std::string& sensor);
  bool EveryTicks(uint64_t tick, double rate_hz, double period_s) const;

  RobotModel model_;
  ExteroceptiveParams params_;
  std::map<std::string, NoiseStream> streams_;
};

}  // namespace fleetnav::sim
