// RGVC_FUZZ_TRACE=1 for the culler fuzz targets: every cull prints the scene as it stands (a scene file
// that `rgvc cull` replays) and its PVS, so that a finding can be followed step by step. Include after
// the dimension's RandomScenes header (reference::toJson).
#pragma once

#include "rgvc/dynamics/Culler.hpp"

#include <cstdio>
#include <cstdlib>
#include <map>
#include <string>
#include <vector>

namespace rgvc::fuzz {

inline const bool kTrace = std::getenv("RGVC_FUZZ_TRACE") != nullptr;

template <int D>
void traceCull(const Culler<D>& culler, const std::map<ObjectId, Shape<D>>& objects, const Camera<D>& cam,
               const CullResult& r) {
    std::vector<ObjectDesc<D>> descs;
    for (const auto& [id, s] : objects) descs.push_back({id, s, true, 0});
    std::string pvs;
    for (ObjectId id : r.pvs) pvs += (pvs.empty() ? "" : " ") + std::to_string(id);
    std::fprintf(stderr,
                 "cull: PVS [%s], outside grid %zu, voxels visited %zu, hidden objects %zu, TBVs created %zu revealed %zu\n%s\n",
                 pvs.c_str(), std::size_t(r.stats.objectsOutsideGrid), std::size_t(r.stats.voxelsVisited),
                 std::size_t(r.stats.hiddenObjects), std::size_t(r.stats.tbvsCreated), std::size_t(r.stats.tbvsRevealed),
                 reference::toJson(culler.grid(), descs, cam).c_str());
}

} // namespace rgvc::fuzz
