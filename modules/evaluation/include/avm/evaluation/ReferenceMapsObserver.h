// The reference maps of a run ([pipeline] reference_maps = true) as an
// observer of it (avm/pipeline/FrameObserver.h), which avm-map connects: every
// frame the map inserts goes, once inserted, into ReferenceOctoMaps with the
// free-only boxes that insertion used, in the map's order (the map rebuild's
// frames too, after the map started over); at the end the finished map is
// compared with them, into stats.json "reference".
#pragma once

#include <optional>

#include "avm/evaluation/ReferenceOctoMaps.h"
#include "avm/pipeline/FrameObserver.h"

namespace avm::evaluation
{
class ReferenceMapsObserver : public pipeline::FrameObserver
{
   public:
	/** Throws std::invalid_argument before the first frame of a resumed or
	 *  continued run: the reference maps would lack the earlier frames. */
	bool betweenFrames(pipeline::RunState& run) override;
	void onFrameInserted(const pipeline::InsertedFrame& frame) override;
	void onMapStartedOver() override;
	/** Compares the finished map with the reference maps: stats.json "reference". */
	void writeStats(const pipeline::FinishedRun& run, io::JsonWriter& stats) override;
	void onRunFinished(const pipeline::FinishedRun& run) override;
	void onRunFailed(const pipeline::RunState& run) override;

	/** The last run's comparison, once its stats.json was written. */
	const std::optional<TReferenceComparison>& comparison() const { return m_comparison; }

   private:
	/** Ready for the next run. */
	void forgetRun();

	std::optional<ReferenceOctoMaps> m_maps;  // of the run under way, from its first insertion
	bool m_started = false;                   // the run under way was checked
	std::optional<TReferenceComparison> m_comparison;
};
}  // namespace avm::evaluation
