#include "avm/evaluation/ReferenceMapsObserver.h"

#include <stdexcept>
#include <utility>

#include "avm/pipeline/MappingPipeline.h"
#include "avm/plugin/CAdaptiveOctoMap.h"

namespace avm::evaluation
{
namespace
{
void writeComparison(io::JsonWriter& json, const TReferenceComparison& c, const io::TimingSummary& mapCpu)
{
	const auto tree = [&](const char* name, const TReferenceComparison::Tree& t)
	{
		json.beginObject(name)
			.value("resolution_m", t.resolution)
			.value("occupied_voxels", t.occupiedLeaves)
			.value("memory_bytes", t.memoryBytes)
			.value("bt_bytes", t.binaryBytes)
			.value("insert_mean_ms", t.meanInsertMs)
			.endObject();
	};
	json.beginObject("reference");
	tree("single_high", c.high);
	tree("single_low", c.low);
	json.value("adaptive_memory_bytes", c.adaptiveMemoryBytes)
		.value("adaptive_bt_bytes", c.adaptiveBinaryBytes)
		.value("memory_share_of_single_high_all_pixels", c.memoryShare(c.adaptiveMemoryBytes))
		.value("bt_share_of_single_high_all_pixels", c.binaryShare(c.adaptiveBinaryBytes))
		.value("inside_regions_occupied_adaptive", c.insideAdaptive)
		.value("inside_regions_occupied_single_high_all_pixels", c.insideReference)
		.value("inside_regions_iou_vs_single_high_all_pixels", c.insideIoU)
		.value("inside_regions_occupied_single_high_moving_free_only", c.insideFreeOnlyReference)
		.value("inside_regions_iou_vs_single_high_moving_free_only", c.insideFreeOnlyIoU)
		.value("outside_regions_occupied_adaptive", c.outsideAdaptive)
		.value("outside_regions_occupied_single_low", c.outsideReference)
		.value("outside_regions_iou", c.outsideIoU)
		.value("map_cpu_speedup_vs_single_high", c.speedup(mapCpu.meanMs))
		.endObject();
}
}  // namespace

bool ReferenceMapsObserver::betweenFrames(pipeline::RunState& run)
{
	if (std::exchange(m_started, true)) return true;
	if (run.resumed() || run.lastFrame())
		throw std::invalid_argument(
			"a run with [pipeline] reference_maps = true cannot be resumed or continue another");
	return true;
}

void ReferenceMapsObserver::onFrameInserted(const pipeline::InsertedFrame& frame)
{
	if (!m_maps)
	{
		const auto& c = frame.map.creationOptions();
		m_maps.emplace(c.high.resolution, c.low.resolution, c.high.maxRange, c.low.maxRange);
	}
	m_maps->insert(frame.observation, frame.pose, frame.freeOnlyBoxes);
}

void ReferenceMapsObserver::onMapStartedOver()
{
	if (m_maps) m_maps->clear();
}

void ReferenceMapsObserver::writeStats(const pipeline::FinishedRun& run, io::JsonWriter& stats)
{
	m_comparison = m_maps->compare(run.map);
	writeComparison(stats, *m_comparison, run.summary.mapCpu);
}

void ReferenceMapsObserver::onRunFinished(const pipeline::FinishedRun& /*run*/) { forgetRun(); }

void ReferenceMapsObserver::onRunFailed(const pipeline::RunState& /*run*/) { forgetRun(); }

void ReferenceMapsObserver::forgetRun()
{
	m_maps.reset();
	m_started = false;
}
}  // namespace avm::evaluation
