// A model's configuration per world (docs/architecture.md, "Worlds"): one
// Config for each world of a swarm, set parameter by parameter through the
// model's table (the same rows, names, ranges and checks as a scenario's),
// and their device blocks laid out one after another (world k's block at
// k * device_floats(), the offset the kernels add).
#pragma once
#include <cmath>
#include <cstdint>
#include <functional>
#include <string>
#include <vector>

#include "core/error.hpp"
#include "params/param_table.hpp"

namespace swarmcl {

// The row of `key` in `table`, or Error(InvalidArgument) naming the keys.
const Param& world_param_row(const ParamTable& table, const std::string& key);

// Checks values[k * components + a] for world k (count = worlds x the row's
// components): Error(InvalidArgument) naming the parameter, the world and
// the valid range for the first value outside it.
void check_world_values(const ParamTable& table, const Param& row, const double* values, size_t count,
                        uint32_t worlds);

// Error(InvalidArgument) "<model> model <key> cannot differ between worlds:
// <why>" where the row is one for every world (Param::one_world) and the
// worlds' values differ.
void check_same_in_every_world(const ParamTable& table, const Param& row, const double* values, uint32_t worlds);

template <class Config>
class WorldConfigs {
public:
    // Every world starts as `config`.
    WorldConfigs(const ParamTable& table, const Config& config, uint32_t worlds)
        : table_(&table), configs_(worlds, config) {}

    uint32_t worlds() const { return uint32_t(configs_.size()); }
    const Config& operator[](uint32_t k) const { return configs_[k]; }

    // Parameter `key` of every world: values[k * components + a].  Every
    // world's new config is checked (the row's range, then the whole table
    // and `also`, e.g. what must stay the same in every world) before any
    // changes: an error leaves all of them as they were.
    void set(const std::string& key, const double* values, size_t count,
             const std::function<void(const Config& changed, uint32_t world)>& also = {}) {
        const Param& row = world_param_row(*table_, key);
        check_world_values(*table_, row, values, count, worlds());
        check_same_in_every_world(*table_, row, values, worlds());
        std::vector<Config> next = configs_;
        for (uint32_t k = 0; k < worlds(); ++k) {
            for (int a = 0; a < row.components(); ++a) row.set(&next[k], values[size_t(k) * row.components() + a], a);
            try {
                table_->validate(&next[k]);
                if (also) also(next[k], k);
            } catch (const Error& e) {
                fail(e.status(), "world " + std::to_string(k) + ": " + e.what());
            }
        }
        configs_ = std::move(next);
    }

    // What the table's rows cannot hold (a model's structured parts, e.g.
    // the path model's goals): apply(config, k) changes world k's copy, then
    // every world is checked as set() checks it; an error leaves all of
    // them as they were.
    void change(const std::function<void(Config& config, uint32_t world)>& apply,
                const std::function<void(const Config& changed, uint32_t world)>& also = {}) {
        std::vector<Config> next = configs_;
        for (uint32_t k = 0; k < worlds(); ++k) {
            try {
                apply(next[k], k);
                table_->validate(&next[k]);
                if (also) also(next[k], k);
            } catch (const Error& e) {
                fail(e.status(), "world " + std::to_string(k) + ": " + e.what());
            }
        }
        configs_ = std::move(next);
    }

    // Parameter `key` of every world, as set() takes it.
    std::vector<double> get(const std::string& key) const {
        const Param& row = world_param_row(*table_, key);
        std::vector<double> out;
        for (const Config& c : configs_)
            for (int a = 0; a < row.components(); ++a) out.push_back(row.get(const_cast<Config*>(&c), a));
        return out;
    }

    // The keys of the parameters that differ between the worlds (what a
    // checkpoint keeps beside the first world's descriptor).
    std::vector<std::string> varied_keys() const {
        std::vector<std::string> out;
        for (const Param& p : table_->params()) {
            const std::vector<double> v = get(p.key);
            for (size_t i = p.components(); i < v.size(); ++i)
                if (v[i] != v[i % p.components()] && !(std::isnan(v[i]) && std::isnan(v[i % p.components()]))) {
                    out.push_back(p.key);
                    break;
                }
        }
        return out;
    }

    // The worlds' device blocks, one after another.
    std::vector<float> device_blocks() const {
        const size_t floats = table_->device_floats() ? table_->device_floats() : 1;
        std::vector<float> out(floats * configs_.size(), 0.0f);
        for (size_t k = 0; k < configs_.size(); ++k)
            table_->write_device_block(const_cast<Config*>(&configs_[k]), out.data() + k * floats);
        return out;
    }

private:
    const ParamTable* table_;
    std::vector<Config> configs_;
};

}  // namespace swarmcl
