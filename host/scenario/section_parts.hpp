// Parts of a scenario file that several model sections read the same way:
// the noise object and the obstacles (analytic boundaries or meshes).
#pragma once
#include <string>
#include <vector>

#include <nlohmann/json_fwd.hpp>

#include "fields/noise_field.hpp"
#include "shapes/triangle_mesh.hpp"
#include "swarm/swarm.hpp"

namespace swarmcl {

class JsonObject;

NoiseConfig read_noise(const nlohmann::json& j, const std::string& path);
// A noise type named by o[key] ("curl", "perlin", "white", "gaussian").
NoiseType read_noise_type(JsonObject& o, const std::string& key, NoiseType def);
// NoiseField::validate of `noise` with the domain as its default region,
// reported as "model.noise: ...".
void check_noise_in_domain(NoiseConfig noise, const SwarmConfig& swarm);

// An analytic obstacle (sphere, box, plane) of the field-like models.
Boundary read_obstacle(const nlohmann::json& j, const std::string& path);
// Every entry of `obstacles` (may be nullptr) as read_obstacle.
std::vector<Boundary> read_obstacles(const nlohmann::json* obstacles);
// A mesh obstacle (box, sphere, cylinder, OBJ file) of the path and force
// models, built by shapes/obstacle_spec.
TriangleMesh read_mesh_obstacle(const nlohmann::json& j, const std::string& path, const std::string& base_dir);

}  // namespace swarmcl
