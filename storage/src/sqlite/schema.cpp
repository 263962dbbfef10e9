#include "fleetnav/storage/sqlite/schema.hpp"

namespace fleetnav::storage {

const std::vector<std::string>& FleetSchemaMigrations() {
  static const std::vector<std::string> kMigrations = {
      // 1: versioned maps.
      R"sql(
        CREATE TABLE maps (
          map_id TEXT NOT NULL,
          version INTEGER NOT NULL,
          width INTEGER NOT NULL,
          height INTEGER NOT NULL,
          resolution_m REAL NOT NULL,
          origin_x_m REAL NOT NULL,
          origin_y_m REAL NOT NULL,
          origin_yaw_rad REAL NOT NULL,
          cells BLOB NOT NULL,
          description TEXT NOT NULL DEFAULT '',
          created_unix_ms INTEGER NOT NULL,
          PRIMARY KEY (map_id, version)
        );
      )sql",
      // 2: marker sets, routes, robots and jobs with their events.
      R"sql(
        CREATE TABLE marker_sets (
          map_id TEXT NOT NULL,
          version INTEGER NOT NULL,
          yaml TEXT NOT NULL,
          created_unix_ms INTEGER NOT NULL,
          PRIMARY KEY (map_id, version)
        );
        CREATE TABLE routes (
          name TEXT NOT NULL,
          version INTEGER NOT NULL,
          map_id TEXT NOT NULL,
          yaml TEXT NOT NULL,
          created_unix_ms INTEGER NOT NULL,
          PRIMARY KEY (name, version)
        );
        CREATE INDEX routes_by_map ON routes (map_id);
        CREATE TABLE robots (
          robot_id TEXT PRIMARY KEY,
          kind_name TEXT NOT NULL,
          capabilities TEXT NOT NULL,
          software_version TEXT NOT NULL,
          last_seen_unix_ms INTEGER NOT NULL
        );
        CREATE TABLE jobs (
          seq INTEGER PRIMARY KEY AUTOINCREMENT,
          job_id TEXT NOT NULL UNIQUE,
          state INTEGER NOT NULL,
          route_name TEXT NOT NULL,
          route_version INTEGER NOT NULL,
          map_id TEXT NOT NULL,
          has_goal INTEGER NOT NULL,
          goal_x_m REAL NOT NULL,
          goal_y_m REAL NOT NULL,
          goal_yaw_rad REAL NOT NULL,
          requested_robot_id TEXT NOT NULL,
          assigned_robot_id TEXT NOT NULL,
          priority INTEGER NOT NULL,
          idempotency_key TEXT,
          on_robot_lost INTEGER NOT NULL,
          created_unix_ms INTEGER NOT NULL,
          updated_unix_ms INTEGER NOT NULL,
          progress_fraction REAL NOT NULL,
          reason TEXT NOT NULL
        );
        CREATE UNIQUE INDEX jobs_by_key ON jobs (idempotency_key) WHERE idempotency_key IS NOT NULL;
        CREATE INDEX jobs_by_state ON jobs (state);
        CREATE TABLE job_events (
          job_id TEXT NOT NULL REFERENCES jobs (job_id) ON DELETE CASCADE,
          sequence INTEGER NOT NULL,
          type INTEGER NOT NULL,
          unix_ms INTEGER NOT NULL,
          robot_id TEXT NOT NULL,
          action_index INTEGER NOT NULL,
          progress_fraction REAL NOT NULL,
          mode INTEGER NOT NULL,
          reason TEXT NOT NULL,
          state INTEGER NOT NULL,
          PRIMARY KEY (job_id, sequence)
        );
      )sql",
      // 3: down-sampled pose history.
      R"sql(
        CREATE TABLE pose_history (
          robot_id TEXT NOT NULL,
          unix_ms INTEGER NOT NULL,
          stamp_ns INTEGER NOT NULL,
          x_m REAL NOT NULL,
          y_m REAL NOT NULL,
          yaw_rad REAL NOT NULL
        );
        CREATE INDEX pose_history_by_robot ON pose_history (robot_id, unix_ms);
        CREATE INDEX pose_history_by_time ON pose_history (unix_ms);
      )sql",
      // 4: operator tokens made through AccessService (hashes only).
      R"sql(
        CREATE TABLE operator_tokens (
          name TEXT PRIMARY KEY,
          role_name TEXT NOT NULL,
          sha256_hex TEXT NOT NULL UNIQUE,
          created_unix_ms INTEGER NOT NULL
        );
      )sql",
      // 5: the lease that makes one fleetnavd replica the leader of its site (used on
      // PostgreSQL, where replicas share the database; kept here so the versions agree).
      R"sql(
        CREATE TABLE site_leases (
          site TEXT PRIMARY KEY,
          holder TEXT NOT NULL,
          address TEXT NOT NULL,
          epoch INTEGER NOT NULL,
          expires_unix_ms INTEGER NOT NULL
        );
      )sql",
      // 6: zone sets (issue 39), versioned per map like marker sets.
      R"sql(
        CREATE TABLE zone_sets (
          map_id TEXT NOT NULL,
          version INTEGER NOT NULL,
          yaml TEXT NOT NULL,
          created_unix_ms INTEGER NOT NULL,
          PRIMARY KEY (map_id, version)
        );
      )sql",
      // 7: operators' stops in force (issue 39), one per scope: map "" and zone "" for the
      // whole fleet; the zone's outline kept as "x y;x y;...".
      R"sql(
        CREATE TABLE stops (
          map_id TEXT NOT NULL,
          zone TEXT NOT NULL,
          polygon TEXT NOT NULL,
          reason TEXT NOT NULL,
          created_unix_ms INTEGER NOT NULL,
          PRIMARY KEY (map_id, zone)
        );
      )sql",
  };
  return kMigrations;
}

SqliteOpenOptions FleetDatabaseOptions(Durability durability) {
  SqliteOpenOptions options;
  options.durability = durability;
  options.application_id = kFleetApplicationId;
  options.legacy_table = "maps";
  return options;
}

}  // namespace fleetnav::storage
