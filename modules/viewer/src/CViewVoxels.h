// avm::viewer::CViewVoxels — the live view's voxels: one COctoMapVoxels kept
// in the scene for the view's life and refilled by each draw, instead of a new
// one per draw. MRPT 2.5.8 turns every voxel into 12 triangles of 108 bytes,
// kept on the CPU and copied into an OpenGL buffer; a new object per draw made
// and freed those (tens of MB for a few thousand voxels) at every redraw, two
// at a time while the old one waited for the GL thread, and the freed blocks
// stayed with the threads' malloc arenas. Refilled in place, the vectors keep
// their capacity and the OpenGL buffer its name. And only a cube's faces that
// no neighbour of the same size in the same set covers are drawn: a wall of
// voxels shows its two sides, not every cube's six faces.
#pragma once

#include <mrpt/opengl/COctoMapVoxels.h>

#include <memory>

namespace avm::viewer
{
class CViewVoxels : public mrpt::opengl::COctoMapVoxels
{
   public:
	using Ptr = std::shared_ptr<CViewVoxels>;

	/** Empties set `set` for push_back_Voxel() to refill; keeps its capacity. */
	void clearVoxels(unsigned set);

   protected:
	/** Never drawn as points: MRPT 2.5.8's own appends the centres to the
	 *  point buffer at every update without clearing it, which an object
	 *  refilled for the whole run would grow without bound. */
	void onUpdateBuffers_Points() override;
	/** The visible sets' exposed faces, two triangles each. */
	void onUpdateBuffers_Triangles() override;
};
}  // namespace avm::viewer
