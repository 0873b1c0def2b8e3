// A table from handle ids to live objects.  Ids are never reused, so a
// destroyed handle, a handle of another type or random bits are all found
// missing (SWCL_ERROR_INVALID_HANDLE) instead of being dereferenced.
#pragma once
#include <cstdint>
#include <memory>
#include <mutex>
#include <unordered_map>

#include "core/error.hpp"

namespace swarmcl {

template <typename T>
class HandleRegistry {
public:
    // `tag` goes into the top byte so ids of different kinds never collide.
    explicit HandleRegistry(uint8_t tag, const char* kind) : tag_(tag), kind_(kind) {}

    uint64_t add(std::shared_ptr<T> object) {
        std::lock_guard<std::mutex> lock(mutex_);
        const uint64_t id = (uint64_t(tag_) << 56) | ++counter_;
        objects_.emplace(id, std::move(object));
        return id;
    }

    std::shared_ptr<T> get(uint64_t id) const {
        std::lock_guard<std::mutex> lock(mutex_);
        auto it = objects_.find(id);
        if (it == objects_.end()) fail(Status::InvalidHandle, missing(id));
        return it->second;
    }

    // Removes the entry; the object dies when the last user lets go of it.
    void remove(uint64_t id) {
        std::shared_ptr<T> doomed;
        {
            std::lock_guard<std::mutex> lock(mutex_);
            auto it = objects_.find(id);
            if (it == objects_.end()) fail(Status::InvalidHandle, missing(id));
            doomed = std::move(it->second);
            objects_.erase(it);
        }
    }

private:
    std::string missing(uint64_t id) const {
        if (id == 0) return std::string("null ") + kind_ + " handle";
        return std::string(kind_) + " handle " + std::to_string(id) + " is not a live " + kind_ +
               " (destroyed, never created, or of another type)";
    }

    uint8_t tag_;
    const char* kind_;
    mutable std::mutex mutex_;
    uint64_t counter_ = 0;
    std::unordered_map<uint64_t, std::shared_ptr<T>> objects_;
};

}  // namespace swarmcl
