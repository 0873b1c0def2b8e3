// Checkpoints: a swarm with its model to a file and back
// (host/models/swarm_checkpoint.hpp, docs/checkpoint-format.md).
#include "capi_common.hpp"
#include "models/swarm_checkpoint.hpp"

using namespace swarmcl;
using namespace swarmcl::capi;

extern "C" {

swcl_status swcl_swarm_save(swcl_swarm swarm, const char* path) {
    return with_swarm(__func__, swarm, [&](Swarm& s) {
        require(path != nullptr && *path, "path is NULL or empty");
        save_swarm(s, path);
    });
}

swcl_status swcl_swarm_load(swcl_context context, const char* path, swcl_swarm* out) {
    return guarded(__func__, [&] {
        require(path != nullptr && *path, "path is NULL or empty");
        check_out(out, "out");
        auto ctx = contexts().get(context.id);
        std::shared_ptr<Swarm> swarm = load_swarm(std::move(ctx), path);
        out->id = swarms().add(std::move(swarm));
    });
}

}  // extern "C"
