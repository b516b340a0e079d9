// CullerTraits<D>: what differs between the 2D and the 3D culler, chosen at compile time: the view
// region (ViewWedge / ViewFrustum), the per-voxel traversal (FrustumTraversal2D / FrustumTraversal3D) and
// its statistics, the brick traversal (BrickTraversal2D / BrickTraversal3D), the occlusion buffer that refines the grid's PVS (OcclusionBuffer2D / OcclusionBuffer3D),
// and the grid limits. Internal to rgvc::dynamics (Culler<D>::Impl, CullerImpl.hpp).
#pragma once

#include "rgvc/dynamics/Culler.hpp"

#include "rgvc/grid/BrickTraversal2D.hpp"
#include "rgvc/grid/BrickTraversal3D.hpp"
#include "rgvc/grid/FrustumTraversal2D.hpp"
#include "rgvc/grid/FrustumTraversal3D.hpp"
#include "rgvc/grid/OcclusionBuffer2D.hpp"
#include "rgvc/grid/OcclusionBuffer3D.hpp"
#include "rgvc/grid/ViewFrustum.hpp"
#include "rgvc/grid/ViewWedge.hpp"
#include "rgvc/grid/VoxelStorage.hpp"

#include <cstdint>
#include <string>

namespace rgvc::culler_detail {

template <int D> struct CullerTraits;

template <> struct CullerTraits<2> {
    using View = ViewWedge;
    using Buffer = OcclusionBuffer2D;
    static int bufferSize(const CullerOptions& o) { return o.occlusionBufferBins; }
    /// Over the scene's DenseStorage (Culler::cull) or a view's stamps over it (ViewStorage, cullViews).
    template <class S> using Traversal = FrustumTraversal2D<S>;
    template <class S> using BrickTraversal = BrickTraversal2D<S>;
    static void checkGrid(const GridGeometry2& grid) {
        for (int a = 0; a < 2; ++a)
            if (grid.resolution()[a] > kMaxShadowExtent)
                throw InvalidInput("grid.resolution", "at most " + std::to_string(kMaxShadowExtent) +
                                                          " voxels per axis in 2D, got " +
                                                          std::to_string(grid.resolution()[a]));
    }
    /// reportEveryVoxel: the 2D traversal reports every visited voxel not in H anyway.
    template <class S, class OnVoxel>
    static void traverse(Traversal<S>& t, const GridGeometry2& grid, S& storage, const View& view,
                         std::uint32_t stamp, const CullerOptions& options, bool /*reportEveryVoxel*/,
                         bool /*deferCaps*/, CullStats& st, OnVoxel&& onVoxel) {
        TraversalOptions2D topt;
        topt.occlusion = options.occlusion;
        topt.extension = options.occluderExtension;
        const TraversalStats2D ts = t.run(grid, storage, view, stamp, topt, onVoxel);
        st.layers = ts.layers;
        st.voxelsVisited = ts.voxelsVisited;
        st.voxelsOccluded = ts.voxelsOccluded;
        st.occludersExtended = ts.occludersExtended;
        st.occluderVoxels = ts.occluderVoxels;
        st.shadows = ts.shadows;
        st.voxelsMarkedOccluded = ts.voxelsMarkedOccluded;
        st.earlyTermination = ts.earlyTermination;
        st.occlusionSkipped = !ts.opaqueMet;
    }
};

template <> struct CullerTraits<3> {
    using View = ViewFrustum;
    using Buffer = OcclusionBuffer3D;
    static int bufferSize(const CullerOptions& o) { return o.occlusionBufferRows; }
    template <class S> using Traversal = FrustumTraversal3D<S>;
    template <class S> using BrickTraversal = BrickTraversal3D<S>;
    static void checkGrid(const GridGeometry3&) {}
    template <class S, class OnVoxel>
    static void traverse(Traversal<S>& t, const GridGeometry3& grid, S& storage, const View& view,
                         std::uint32_t stamp, const CullerOptions& options, bool reportEveryVoxel, bool deferCaps,
                         CullStats& st, OnVoxel&& onVoxel) {
        TraversalOptions3D topt;
        topt.deferCaps = deferCaps;
        topt.occlusion = options.occlusion;
        topt.exponentialCaps = options.occluderExtension;
        topt.reportEveryVoxel = reportEveryVoxel;
        const TraversalStats3D ts = t.run(grid, storage, view, stamp, topt, onVoxel);
        st.layers = ts.layers;
        st.voxelsVisited = ts.voxelsVisited;
        st.voxelsOccluded = ts.voxelsOccluded;
        st.occludersExtended = ts.opaqueVisited;
        st.occluderVoxels = ts.capVoxels;
        st.shadows = ts.capFaces;
        st.voxelsMarkedOccluded = ts.voxelsOccluded;
        st.earlyTermination = ts.earlyTermination;
        st.occlusionSkipped = ts.opaqueVisited == 0;
        st.capsDeferred = deferCaps;
        st.capsFromShell = ts.capsFromShell;
    }
};

} // namespace rgvc::culler_detail
