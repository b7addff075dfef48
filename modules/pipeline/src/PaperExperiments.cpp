#include "avm/pipeline/PaperExperiments.h"

#include <mrpt/config/CConfigFileMemory.h>
#include <mrpt/system/datetime.h>
#include <unistd.h>

#include <cstdio>
#include <fstream>
#include <optional>
#include <sstream>
#include <thread>

#include "avm/io/AtomicFile.h"
#include "avm/maps/CAdaptiveOctoMap.h"
#include "avm/pipeline/MappingPipeline.h"

namespace avm::pipeline
{
namespace fs = std::filesystem;

namespace
{
const std::string kCreation = "map_adaptiveOctoMap_00_creationOpts";
const std::string kInsertion = "map_adaptiveOctoMap_00_insertOpts";

struct Override
{
	std::string section, key, value;
};

struct Outcome
{
	RunSummary summary;
	CAdaptiveOctoMap::TTreeStats low, high;
	fs::path dir;
	std::size_t occupied() const { return low.occupiedLeaves + high.occupiedLeaves; }
	double btKiB() const { return (low.binaryBytes + high.binaryBytes) / 1024.0; }
	double memoryKiB() const { return (low.memoryBytes + high.memoryBytes) / 1024.0; }
};

std::string readText(const fs::path& file)
{
	std::ifstream in(file);
	if (!in) throw std::runtime_error(file.string() + ": cannot read");
	std::stringstream s;
	s << in.rdbuf();
	return s.str();
}

std::string machineDescription()
{
	std::ifstream cpu("/proc/cpuinfo");
	std::string line, model = "unknown CPU";
	while (std::getline(cpu, line))
		if (line.rfind("model name", 0) == 0)
		{
			model = line.substr(line.find(':') + 2);
			break;
		}
	return model + ", " + std::to_string(std::thread::hardware_concurrency()) + " cores";
}

class Experiments
{
   public:
	Experiments(const PaperExperimentSettings& s, mrpt::system::COutputLogger& log)
		: m_settings(s), m_log(log), m_baseIni(readText(s.baseIni))
	{
	}

	/** One run of ini/paper.ini with the overrides, in its own folder. */
	Outcome run(const std::string& name, PoseSource poses, const std::vector<Override>& overrides)
	{
		mrpt::config::CConfigFileMemory ini(m_baseIni);
		// Synchronous detection: the same frames detected in every run.
		ini.write("pipeline", "async_detection", "false");
		for (const auto& o : overrides) ini.write(o.section, o.key, o.value);
		Outcome out;
		out.dir = m_settings.workDir / (name + "_" + toString(poses));
		MappingPipeline pipeline(ini, m_settings.projectRoot);
		pipeline.setMinLoggingLevel(mrpt::system::LVL_WARN);
		pipeline.setPoseSource(poses);
		out.summary = pipeline.run(m_settings.rawlog, out.dir);
		out.low = pipeline.map().lowResolutionStats();
		out.high = pipeline.map().highResolutionStats();
		m_log.logFmt(mrpt::system::LVL_INFO, "%-28s %-2s: %zu frames, occupied low %zu high %zu, %.2f KiB .bt\n",
			name.c_str(), toString(poses).c_str(), out.summary.frames, out.low.occupiedLeaves,
			out.high.occupiedLeaves, out.btKiB());
		return out;
	}

   private:
	const PaperExperimentSettings& m_settings;
	mrpt::system::COutputLogger& m_log;
	std::string m_baseIni;
};

/** Table 1's three maps for one policy at one pair of resolutions. */
struct Table1Row
{
	std::string label;
	Outcome lowOnly, highOnly, adaptive;
};

Table1Row table1(Experiments& e, PoseSource poses, const std::string& policy, double low, double high)
{
	char res[64];
	std::snprintf(res, sizeof(res), "%g_%g", low, high);
	const std::vector<Override> resolutions = {
		{kCreation, "low_resolution", std::to_string(low)}, {kCreation, "high_resolution", std::to_string(high)}};
	auto with = [&](std::vector<Override> more) {
		more.insert(more.begin(), resolutions.begin(), resolutions.end());
		return more;
	};
	Table1Row row;
	row.label = policy + " policy, " + std::string(res);
	const std::string tag = std::string(res);
	// No trigger: everything stays in the low tree.
	row.lowOnly = e.run("low_only_" + tag, poses, with({{"pipeline", "detect_every_n", "0"}}));
	// Switched before the first frame: one high-resolution OctoMap.
	row.highOnly = e.run(
		"high_only_" + tag, poses,
		with({{"pipeline", "detect_every_n", "0"}, {kInsertion, "switch_policy", "paper"},
			  {kInsertion, "switch_at_frame", "0"}}));
	row.adaptive = e.run("adaptive_" + policy + "_" + tag, poses, with({{kInsertion, "switch_policy", policy}}));
	return row;
}

struct Table2Column
{
	int highSharePercent;
	Outcome outcome;
};

std::vector<Table2Column> table2(Experiments& e, PoseSource poses)
{
	std::vector<Table2Column> out;
	for (const int share : {0, 30, 50, 70, 100})
	{
		std::vector<Override> o = {{"pipeline", "detect_every_n", "0"}};
		if (share == 100)
			o.push_back({kInsertion, "switch_at_frame", "0"});
		else if (share > 0)
			o.push_back({kInsertion, "switch_at_fraction", std::to_string((100 - share) / 100.0)});
		out.push_back({share, e.run("share_" + std::to_string(share), poses, o)});
	}
	return out;
}

std::string fmt(const char* f, double v)
{
	char buf[64];
	std::snprintf(buf, sizeof(buf), f, v);
	return buf;
}

void copyPicture(const fs::path& from, const fs::path& to)
{
	if (!fs::exists(from)) return;
	fs::create_directories(to.parent_path());
	fs::copy_file(from, to, fs::copy_options::overwrite_existing);
}
}  // namespace

void reproducePaper(const PaperExperimentSettings& s, mrpt::system::COutputLogger& log)
{
	Experiments e(s, log);
	std::vector<PoseSource> sources = {PoseSource::GroundTruth};
	if (s.withOdometry) sources.push_back(PoseSource::VisualOdometry);

	std::ostringstream md;
	md << "# The paper's evaluation on real data\n\n"
	   << "Generated by `" << s.command << "` on "
	   << mrpt::system::dateTimeLocalToString(mrpt::Clock::now()).substr(0, 19) << " (" << machineDescription()
	   << "). Every number below comes from that run; nothing is typed by hand.\n\n"
	   << "Data: `" << s.rawlog.filename().string()
	   << "` (300 frames, 10 s, of Bonn RGB-D Dynamic `rgbd_bonn_crowd`: an office, people walk into "
		  "view after frame ~70). Base configuration: `ini/paper.ini` (paper policy, 1.5 m / 0.5 m, "
		  "detection on every frame, YOLOX-Nano in place of the paper's YOLOv8n), with the changes named "
		  "per row. Voxel counts are the occupied leaves of the pruned trees that the map shows "
		  "(octomap's leaf iterator; in the paper policy a high leaf counts only where the low tree has "
		  "no node, Algorithm 2). Sizes are the `.bt` files (octomap's binary format, low + high tree).\n\n";

	struct PerSource
	{
		PoseSource poses;
		std::vector<Table1Row> rows;
		std::vector<Table2Column> shares;
	};
	std::vector<PerSource> results;
	for (const auto poses : sources)
	{
		PerSource r{poses, {}, {}};
		r.rows.push_back(table1(e, poses, "paper", 1.5, 0.5));
		r.rows.push_back(table1(e, poses, "region", 1.5, 0.5));
		r.rows.push_back(table1(e, poses, "region", 0.20, 0.05));
		r.shares = table2(e, poses);
		results.push_back(std::move(r));
	}

	md << "## Table 1: occupied voxels\n\n"
	   << "| poses | policy, low_high [m] | low only | high only | adaptive | adaptive / high only | switch frame |\n"
	   << "|---|---|---:|---:|---:|---:|---:|\n"
	   << "| (paper) | paper, 1.5_0.5 | 641 | 6415 | 4225 | 0.66 | |\n";
	for (const auto& r : results)
		for (const auto& row : r.rows)
			md << "| " << toString(r.poses) << " | " << row.label << " | " << row.lowOnly.occupied() << " | "
			   << row.highOnly.occupied() << " | " << row.adaptive.occupied() << " | "
			   << fmt("%.2f", double(row.adaptive.occupied()) / std::max<std::size_t>(1, row.highOnly.occupied()))
			   << " | "
			   << (row.adaptive.summary.switchFrame ? std::to_string(*row.adaptive.summary.switchFrame) : "never")
			   << " |\n";

	md << "\n## Table 2: map size against the high-resolution share of the run\n\n"
	   << "Paper policy, 1.5 m / 0.5 m, the switch forced at 100, 70, 50, 30 and 0 % of the frames "
		  "(`switch_at_fraction`, `switch_at_frame = 0`), no detector.\n\n"
	   << "| high-resolution share | 0 % | 30 % | 50 % | 70 % | 100 % |\n|---|---:|---:|---:|---:|---:|\n"
	   << "| (paper) map size [KB] | 0.454 | 1.1 | 1.4 | 1.6 | 1.7 |\n";
	for (const auto& r : results)
	{
		md << "| " << toString(r.poses) << ": .bt size [KiB] |";
		for (const auto& c : r.shares) md << " " << fmt("%.1f", c.outcome.btKiB()) << " |";
		md << "\n| " << toString(r.poses) << ": memory [KiB] |";
		for (const auto& c : r.shares) md << " " << fmt("%.1f", c.outcome.memoryKiB()) << " |";
		md << "\n| " << toString(r.poses) << ": occupied voxels |";
		for (const auto& c : r.shares) md << " " << c.outcome.occupied() << " |";
		md << "\n";
	}

	for (const auto& r : results)
		if (r.poses == PoseSource::VisualOdometry && r.rows[0].adaptive.summary.ateRmse)
			md << "\n## Odometry\n\nThe odometry runs use avm's visual odometry (person masking on). Its ATE RMSE "
				  "against the ground truth (SE(3) alignment) in the adaptive paper-policy run: "
			   << fmt("%.3f", *r.rows[0].adaptive.summary.ateRmse) << " m.\n";

	// What agrees and what does not, decided from the numbers above.
	const auto& gt = results.front();
	const auto& p = gt.rows[0];       // paper policy, 1.5/0.5
	const auto& region = gt.rows[2];  // region policy, 0.20/0.05
	const auto ratio = [](std::size_t a, std::size_t b) { return double(a) / double(std::max<std::size_t>(1, b)); };
	const bool ordered = p.lowOnly.occupied() < p.adaptive.occupied() && p.adaptive.occupied() < p.highOnly.occupied();
	bool growing = true;
	for (std::size_t i = 1; i < gt.shares.size(); ++i)
		growing &= gt.shares[i].outcome.btKiB() >= gt.shares[i - 1].outcome.btKiB();
	const std::string switchFrame =
		p.adaptive.summary.switchFrame ? std::to_string(*p.adaptive.summary.switchFrame) : "never";
	md << "\n## What agrees with the paper, what does not, and why\n\n"
	   << "- Ordering low only < adaptive < high only (paper 641 < 4225 < 6415): "
	   << (ordered ? "**agrees**" : "**does not agree**") << " (ground truth, paper policy: " << p.lowOnly.occupied()
	   << ", " << p.adaptive.occupied() << ", " << p.highOnly.occupied() << "). Algorithm 2 puts a point in the high "
	   << "tree only where the low tree has no node, free or occupied. The switch came at frame " << switchFrame
	   << " of " << p.adaptive.summary.frames << "; after it the adaptive map's high tree holds "
	   << p.adaptive.high.occupiedLeaves << " occupied voxels and its low tree " << p.adaptive.low.occupiedLeaves
	   << " (the low tree no longer changes after the switch, so it is the low map of the first " << switchFrame
	   << " frames). The camera of this sequence moves about 0.85 m in 10 s: by the switch the low tree already "
	   << "has nodes nearly everywhere the later frames look, so little reaches the high tree. In the paper the "
	   << "robot goes on into unseen space after the switch, which the high tree then maps.\n"
	   << "- High only / low only: paper " << fmt("%.1f", 6415.0 / 641.0) << "x, here "
	   << fmt("%.1f", ratio(p.highOnly.occupied(), p.lowOnly.occupied()))
	   << "x. The ratio depends on how much of the scene is surface: 3^3 = 27 is the bound for solid matter, "
		  "thin surfaces give about 3^2 = 9.\n"
	   << "- Adaptive / high only: paper 0.66, here " << fmt("%.2f", ratio(p.adaptive.occupied(), p.highOnly.occupied()))
	   << " for the reason in the first point.\n"
	   << "- Map size grows with the high-resolution share (paper 0.454 → 1.7 KB): "
	   << (growing ? "**agrees**" : "**does not agree**") << " (here " << fmt("%.1f", gt.shares.front().outcome.btKiB())
	   << " → " << fmt("%.1f", gt.shares.back().outcome.btKiB())
	   << " KiB). Absolute sizes do not compare: the paper mapped another, larger scene and does not say how it "
		  "measured KB; here they are octomap `.bt` bytes of this 10 s office sequence.\n"
	   << "- The region policy (avm's default) at 0.20 m / 0.05 m: adaptive / high only = "
	   << fmt("%.2f", ratio(region.adaptive.occupied(), region.highOnly.occupied())) << " ("
	   << region.adaptive.low.occupiedLeaves << " low and " << region.adaptive.high.occupiedLeaves
	   << " high occupied voxels, " << region.adaptive.summary.regions << " person regions added). People walk "
	   << "across most of the near field in this sequence, and overlapping person regions merge into their "
		  "bounding box, so most of what the camera sees ends up in the high-resolution region. No space is held "
		  "twice: low voxels inside a region are removed.\n";

	const fs::path pictures = s.results.parent_path() / "results";
	md << "\n## Pictures\n\nOccupied voxels, low resolution in blue, high resolution in orange, camera trajectory "
		  "in green, person regions in red (ground-truth poses).\n\n";
	for (const auto& [row, name] : {std::pair{&gt.rows[0], "paper"}, {&gt.rows[2], "region"}})
	{
		for (const char* view : {"top", "perspective"})
		{
			const std::string file = std::string(name) + "_adaptive_" + view + ".png";
			copyPicture(row->adaptive.dir / ("map_" + std::string(view) + ".png"), pictures / file);
			md << "![" << row->label << ", " << view << "](results/" << file << ")\n";
		}
	}
	io::writeFileAtomically(s.results, [&](const fs::path& tmp) {
		std::ofstream out(tmp);
		out << md.str();
		if (!out.flush()) throw std::runtime_error(s.results.string() + ": write failed");
	});
}
}  // namespace avm::pipeline
