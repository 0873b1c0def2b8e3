#include "shapes/shape_library.hpp"

#include <cmath>
#include <cstdlib>

#include "core/error.hpp"

namespace swarmcl {
namespace {

constexpr float kPi = 3.14159265358979f;

// Validated mesh from packed arrays, flipped if it came out inward.
TriangleMesh build(const std::vector<float>& xyz, std::vector<uint32_t> idx) {
    TriangleMesh m = make_mesh(xyz, idx);
    if (signed_volume(m) < 0.0)
        for (auto& f : m.triangles) std::swap(f[1], f[2]);
    return m;
}

void push(std::vector<float>& xyz, float x, float y, float z) {
    xyz.push_back(x);
    xyz.push_back(y);
    xyz.push_back(z);
}

void tri(std::vector<uint32_t>& idx, uint32_t a, uint32_t b, uint32_t c) {
    idx.push_back(a);
    idx.push_back(b);
    idx.push_back(c);
}

// A closed outline in the xy plane (star-shaped about the origin) extruded
// from z = -depth/2 to +depth/2: two fans and a side band.
TriangleMesh extrude(const std::vector<std::array<float, 2>>& outline, float depth) {
    std::vector<float> xyz;
    std::vector<uint32_t> idx;
    const uint32_t k = uint32_t(outline.size());
    push(xyz, 0, 0, depth / 2);   // 0: top centre
    push(xyz, 0, 0, -depth / 2);  // 1: bottom centre
    for (const auto& p : outline) push(xyz, p[0], p[1], depth / 2);   // 2 .. k+1
    for (const auto& p : outline) push(xyz, p[0], p[1], -depth / 2);  // k+2 .. 2k+1
    for (uint32_t i = 0; i < k; ++i) {
        const uint32_t j = (i + 1) % k;
        tri(idx, 0, 2 + i, 2 + j);
        tri(idx, 1, 2 + k + j, 2 + k + i);
        tri(idx, 2 + i, 2 + k + i, 2 + k + j);
        tri(idx, 2 + i, 2 + k + j, 2 + j);
    }
    return build(xyz, std::move(idx));
}

// An ellipsoid with radii r centred at c, pitched by `pitch` radians about
// the y axis (legs swinging in the xz plane), then yawed about z.
TriangleMesh part(Vec3f c, Vec3f r, float pitch = 0.0f, float yaw = 0.0f, uint32_t rings = 10,
                  uint32_t segments = 16) {
    TriangleMesh m = ellipsoid_mesh({0, 0, 0}, r, rings, segments);
    const float cp = std::cos(pitch), sp = std::sin(pitch), cy = std::cos(yaw), sy = std::sin(yaw);
    for (auto& v : m.vertices) {
        const float x = cp * v[0] + sp * v[2], z = -sp * v[0] + cp * v[2];
        const float x2 = cy * x - sy * v[1], y2 = sy * x + cy * v[1];
        v = {x2 + c[0], y2 + c[1], z + c[2]};
    }
    return m;
}

// A leg hanging from `hip`, swung by `angle` (radians, + forward along x).
TriangleMesh leg(Vec3f hip, float length, float thickness, float angle) {
    const float h = length / 2;
    return part({hip[0] - h * std::sin(angle), hip[1], hip[2] - h * std::cos(angle)}, {thickness, thickness, h},
                -angle);
}

}  // namespace

TriangleMesh torus_mesh(float major_radius, float minor_radius, uint32_t rings, uint32_t segments) {
    require(major_radius > minor_radius && minor_radius > 0.0f, "torus: needs major > minor > 0");
    std::vector<float> xyz;
    std::vector<uint32_t> idx;
    for (uint32_t i = 0; i < segments; ++i) {
        const float a = 2 * kPi * i / segments;
        for (uint32_t j = 0; j < rings; ++j) {
            const float b = 2 * kPi * j / rings;
            const float rr = major_radius + minor_radius * std::cos(b);
            push(xyz, rr * std::cos(a), rr * std::sin(a), minor_radius * std::sin(b));
        }
    }
    for (uint32_t i = 0; i < segments; ++i)
        for (uint32_t j = 0; j < rings; ++j) {
            const uint32_t i2 = (i + 1) % segments, j2 = (j + 1) % rings;
            tri(idx, i * rings + j, i2 * rings + j, i2 * rings + j2);
            tri(idx, i * rings + j, i2 * rings + j2, i * rings + j2);
        }
    return build(xyz, std::move(idx));
}

TriangleMesh crescent_mesh(float radius, float thickness, uint32_t rings, uint32_t segments) {
    require(radius > 0.0f && thickness > 0.0f && rings >= 4 && segments >= 3, "crescent: bad parameters");
    std::vector<float> xyz;
    std::vector<uint32_t> idx;
    const float phi0 = -0.75f * kPi, phi1 = 0.75f * kPi;
    // Rings 1..rings-1 on the arc; the tips are single points.
    auto centre = [&](float phi) { return std::array<float, 2>{radius * std::cos(phi), radius * std::sin(phi)}; };
    push(xyz, centre(phi0)[0], centre(phi0)[1], 0);  // 0: first tip
    for (uint32_t i = 1; i < rings; ++i) {
        const float s = float(i) / rings, phi = phi0 + s * (phi1 - phi0);
        const float r = thickness * std::sin(kPi * s);  // swells to the middle
        const auto c = centre(phi);
        for (uint32_t j = 0; j < segments; ++j) {
            const float b = 2 * kPi * j / segments;
            push(xyz, c[0] + r * std::cos(b) * std::cos(phi), c[1] + r * std::cos(b) * std::sin(phi),
                 r * std::sin(b));
        }
    }
    const uint32_t last = uint32_t(xyz.size() / 3);
    push(xyz, centre(phi1)[0], centre(phi1)[1], 0);
    auto at = [&](uint32_t ring, uint32_t j) { return 1 + (ring - 1) * segments + j % segments; };
    for (uint32_t j = 0; j < segments; ++j) {
        tri(idx, 0, at(1, j + 1), at(1, j));
        tri(idx, last, at(rings - 1, j), at(rings - 1, j + 1));
    }
    for (uint32_t i = 1; i + 1 < rings; ++i)
        for (uint32_t j = 0; j < segments; ++j) {
            tri(idx, at(i, j), at(i, j + 1), at(i + 1, j + 1));
            tri(idx, at(i, j), at(i + 1, j + 1), at(i + 1, j));
        }
    return build(xyz, std::move(idx));
}

TriangleMesh star_mesh(float outer_radius, float inner_radius, float depth) {
    require(outer_radius > inner_radius && inner_radius > 0.0f && depth > 0.0f, "star: bad parameters");
    std::vector<std::array<float, 2>> outline;
    for (int i = 0; i < 10; ++i) {
        const float a = kPi / 2 + i * kPi / 5, r = (i % 2) ? inner_radius : outer_radius;
        outline.push_back({r * std::cos(a), r * std::sin(a)});
    }
    return extrude(outline, depth);
}

TriangleMesh heart_mesh(float size, float depth, uint32_t outline_points) {
    require(size > 0.0f && depth > 0.0f && outline_points >= 8, "heart: bad parameters");
    // The classic heart curve, centred on its interior point (0, 2.5/17).
    std::vector<std::array<float, 2>> outline;
    for (uint32_t i = 0; i < outline_points; ++i) {
        const float t = 2 * kPi * i / outline_points;
        const float x = 16 * std::pow(std::sin(t), 3.0f);
        const float y = 13 * std::cos(t) - 5 * std::cos(2 * t) - 2 * std::cos(3 * t) - std::cos(4 * t) + 2.5f;
        outline.push_back({size * x / 17, size * y / 17});
    }
    return extrude(outline, depth);
}

TriangleMesh mammoth_mesh() {
    std::vector<TriangleMesh> p;
    p.push_back(part({0, 0, 0.35f}, {0.85f, 0.5f, 0.55f}, 0, 0, 16, 24));       // body
    p.push_back(part({0.8f, 0, 0.65f}, {0.4f, 0.35f, 0.4f}));                   // head
    p.push_back(part({0.95f, 0.35f, 0.7f}, {0.15f, 0.3f, 0.35f}));              // ears
    p.push_back(part({0.95f, -0.35f, 0.7f}, {0.15f, 0.3f, 0.35f}));
    p.push_back(part({1.2f, 0, 0.3f}, {0.1f, 0.1f, 0.35f}, 0.2f));              // trunk
    p.push_back(part({1.3f, 0, -0.15f}, {0.08f, 0.08f, 0.25f}, -0.3f));
    p.push_back(part({1.25f, 0.15f, 0.25f}, {0.05f, 0.05f, 0.35f}, -0.9f));    // tusks
    p.push_back(part({1.25f, -0.15f, 0.25f}, {0.05f, 0.05f, 0.35f}, -0.9f));
    for (float x : {0.5f, -0.5f})
        for (float y : {0.28f, -0.28f}) p.push_back(leg({x, y, 0.0f}, 0.9f, 0.17f, 0.0f));
    p.push_back(part({-0.9f, 0, 0.45f}, {0.2f, 0.04f, 0.04f}, 0.8f));           // tail
    return merged(p);
}

TriangleMesh shark_mesh() {
    std::vector<TriangleMesh> p;
    p.push_back(part({0, 0, 0}, {1.2f, 0.3f, 0.32f}, 0, 0, 16, 24));           // body
    p.push_back(part({1.05f, 0, -0.05f}, {0.35f, 0.2f, 0.18f}));               // snout
    p.push_back(part({0.05f, 0, 0.4f}, {0.28f, 0.04f, 0.28f}, -0.5f));         // dorsal fin
    p.push_back(part({0.35f, 0.38f, -0.18f}, {0.25f, 0.3f, 0.03f}, 0, -0.5f)); // pectoral fins
    p.push_back(part({0.35f, -0.38f, -0.18f}, {0.25f, 0.3f, 0.03f}, 0, 0.5f));
    p.push_back(part({-1.25f, 0, 0.3f}, {0.12f, 0.03f, 0.4f}, 0.6f));          // tail, upper lobe
    p.push_back(part({-1.2f, 0, -0.22f}, {0.1f, 0.03f, 0.25f}, -0.6f));        // lower lobe
    return merged(p);
}

TriangleMesh horse_mesh(float phase) {
    require(std::isfinite(phase), "horse: phase must be finite");
    const float w = 2 * kPi * (phase - std::floor(phase));
    const float swing = 0.55f;  // radians, the gallop's leg amplitude
    std::vector<TriangleMesh> p;
    p.push_back(part({0, 0, 0.9f}, {0.75f, 0.28f, 0.3f}, 0, 0, 14, 24));       // body
    p.push_back(part({0.8f, 0, 1.25f}, {0.15f, 0.13f, 0.38f}, 0.6f));          // neck
    p.push_back(part({1.12f, 0, 1.5f}, {0.3f, 0.11f, 0.12f}, -0.4f));          // head
    p.push_back(part({-0.9f, 0, 0.85f}, {0.35f, 0.06f, 0.07f}, 0.7f));         // tail
    // Gallop: front and hind pairs in anti-phase, left lagging right.
    p.push_back(leg({0.5f, 0.15f, 0.75f}, 0.8f, 0.08f, swing * std::sin(w)));
    p.push_back(leg({0.5f, -0.15f, 0.75f}, 0.8f, 0.08f, swing * std::sin(w + 0.6f)));
    p.push_back(leg({-0.5f, 0.15f, 0.75f}, 0.8f, 0.09f, -swing * std::sin(w)));
    p.push_back(leg({-0.5f, -0.15f, 0.75f}, 0.8f, 0.09f, -swing * std::sin(w + 0.6f)));
    TriangleMesh m = merged(p);
    for (auto& v : m.vertices) v[2] -= 0.8f;  // centre the figure near the origin
    return m;
}

std::vector<std::string> generated_shape_names() {
    return {"sphere", "torus", "moon", "star", "heart", "mammoth", "shark", "horse", "horse:<phase>"};
}

TriangleMesh generated_shape(const std::string& name) {
    if (name == "sphere") return sphere_mesh({0, 0, 0}, 1.0f, 24, 48);
    if (name == "torus") return torus_mesh(0.8f, 0.3f);
    if (name == "moon") return crescent_mesh(0.8f, 0.45f);
    if (name == "star") return star_mesh(1.0f, 0.42f, 0.3f);
    if (name == "heart") return heart_mesh(1.0f, 0.3f);
    if (name == "mammoth") return mammoth_mesh();
    if (name == "shark") return shark_mesh();
    if (name == "horse") return horse_mesh(0.0f);
    if (name.rfind("horse:", 0) == 0) {
        const std::string num = name.substr(6);
        char* end = nullptr;
        const float phase = std::strtof(num.c_str(), &end);
        if (!num.empty() && end == num.c_str() + num.size() && std::isfinite(phase)) return horse_mesh(phase);
    }
    std::string known;
    for (const auto& n : generated_shape_names()) known += (known.empty() ? "" : ", ") + n;
    fail(Status::InvalidArgument, "unknown generated shape \"" + name + "\" (known: " + known + ")");
}

}  // namespace swarmcl
