#include "fleetnav/storage/postgres/pg_schema.hpp"

namespace fleetnav::storage {

// SQLite's INTEGER is 64-bit: BIGINT here; REAL is DOUBLE PRECISION; BLOB is BYTEA.
const std::vector<std::string>& PostgresFleetSchemaMigrations() {
  static const std::vector<std::string> kMigrations = {
      // 1: versioned maps.
      R"sql(
        CREATE TABLE maps (
          map_id TEXT NOT NULL,
          version BIGINT NOT NULL,
          width BIGINT NOT NULL,
          height BIGINT NOT NULL,
          resolution_m DOUBLE PRECISION NOT NULL,
          origin_x_m DOUBLE PRECISION NOT NULL,
          origin_y_m DOUBLE PRECISION NOT NULL,
          origin_yaw_rad DOUBLE PRECISION NOT NULL,
          cells BYTEA NOT NULL,
          description TEXT NOT NULL DEFAULT '',
          created_unix_ms BIGINT NOT NULL,
          PRIMARY KEY (map_id, version)
        );
      )sql",
      // 2: marker sets, routes, robots and jobs with their events.
      R"sql(
        CREATE TABLE marker_sets (
          map_id TEXT NOT NULL,
          version BIGINT NOT NULL,
          yaml TEXT NOT NULL,
          created_unix_ms BIGINT NOT NULL,
          PRIMARY KEY (map_id, version)
        );
        CREATE TABLE routes (
          name TEXT NOT NULL,
          version BIGINT NOT NULL,
          map_id TEXT NOT NULL,
          yaml TEXT NOT NULL,
          created_unix_ms BIGINT NOT NULL,
          PRIMARY KEY (name, version)
        );
        CREATE INDEX routes_by_map ON routes (map_id);
        CREATE TABLE robots (
          robot_id TEXT PRIMARY KEY,
          kind_name TEXT NOT NULL,
          capabilities TEXT NOT NULL,
          software_version TEXT NOT NULL,
          last_seen_unix_ms BIGINT NOT NULL
        );
        CREATE TABLE jobs (
          seq BIGINT PRIMARY KEY,
          job_id TEXT NOT NULL UNIQUE,
          state BIGINT NOT NULL,
          route_name TEXT NOT NULL,
          route_version BIGINT NOT NULL,
          map_id TEXT NOT NULL,
          has_goal BIGINT NOT NULL,
          goal_x_m DOUBLE PRECISION NOT NULL,
          goal_y_m DOUBLE PRECISION NOT NULL,
          goal_yaw_rad DOUBLE PRECISION NOT NULL,
          requested_robot_id TEXT NOT NULL,
          assigned_robot_id TEXT NOT NULL,
          priority BIGINT NOT NULL,
          idempotency_key TEXT,
          on_robot_lost BIGINT NOT NULL,
          created_unix_ms BIGINT NOT NULL,
          updated_unix_ms BIGINT NOT NULL,
          progress_fraction DOUBLE PRECISION NOT NULL,
          reason TEXT NOT NULL
        );
        CREATE UNIQUE INDEX jobs_by_key ON jobs (idempotency_key) WHERE idempotency_key IS NOT NULL;
        CREATE INDEX jobs_by_state ON jobs (state);
        CREATE TABLE job_events (
          job_id TEXT NOT NULL REFERENCES jobs (job_id) ON DELETE CASCADE,
          sequence BIGINT NOT NULL,
          type BIGINT NOT NULL,
          unix_ms BIGINT NOT NULL,
          robot_id TEXT NOT NULL,
          action_index BIGINT NOT NULL,
          progress_fraction DOUBLE PRECISION NOT NULL,
          mode BIGINT NOT NULL,
          reason TEXT NOT NULL,
          state BIGINT NOT NULL,
          PRIMARY KEY (job_id, sequence)
        );
      )sql",
      // 3: down-sampled pose history.
      R"sql(
        CREATE TABLE pose_history (
          robot_id TEXT NOT NULL,
          unix_ms BIGINT NOT NULL,
          stamp_ns BIGINT NOT NULL,
          x_m DOUBLE PRECISION NOT NULL,
          y_m DOUBLE PRECISION NOT NULL,
          yaw_rad DOUBLE PRECISION NOT NULL
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
          created_unix_ms BIGINT NOT NULL
        );
      )sql",
      // 5: the lease that makes one fleetnavd replica the leader of its site. `epoch` grows
      // with every new holder and is the fencing token of the leader's writes; `expires_at`
      // is on the database server's clock, the one clock every replica shares.
      R"sql(
        CREATE TABLE site_leases (
          site TEXT PRIMARY KEY,
          holder TEXT NOT NULL,
          address TEXT NOT NULL,
          epoch BIGINT NOT NULL,
          expires_at TIMESTAMPTZ NOT NULL
        );
        -- Job numbers from a sequence: submissions on several connections do not queue for
        -- the next number (a rolled-back submission leaves a gap).
        CREATE SEQUENCE job_numbers;
        SELECT setval('job_numbers', COALESCE((SELECT MAX(seq) FROM jobs), 0) + 1, false);
      )sql",
      // 6: zone sets (issue 39), versioned per map like marker sets.
      R"sql(
        CREATE TABLE zone_sets (
          map_id TEXT NOT NULL,
          version BIGINT NOT NULL,
          yaml TEXT NOT NULL,
          created_unix_ms BIGINT NOT NULL,
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
          created_unix_ms BIGINT NOT NULL,
          PRIMARY KEY (map_id, zone)
        );
      )sql",
  };
  return kMigrations;
}

}  // namespace fleetnav::storage
