#include "fleetnav/sim/noise.hpp"

namespace fleetnav::sim {
namespace {

// FNV-1a, then a SplitMix64 finaliser: stable across platforms and runs.
uint64_t Mix(uint64_t hash, std::string_view text) {
  for (unsigned char c : text) {
    hash ^= c;
    hash *= 0x100000001B3ull;
  }
  hash ^= 0xFF;  // separator so ("ab", "c") differs from ("a", "bc")
  hash *= 0x100000001B3ull;
  return hash;
}

uint64_t Finalise(uint64_t z) {
  z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ull;
  z = (z ^ (z >> 27)) * 0x94D049BB133111EBull;
  return z ^ (z >> 31);
}

}  // namespace

uint64_t NoiseSeed(uint64_t simulation_seed, std::string_view robot_id, std::string_view sensor) {
  uint64_t hash = 0xCBF29CE484222325ull ^ Finalise(simulation_seed);
  hash = Mix(hash, robot_id);
  hash = Mix(hash, sensor);
  return Finalise(hash);
}

}  // namespace fleetnav::sim
