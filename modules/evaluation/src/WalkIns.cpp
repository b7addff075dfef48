#include "avm/evaluation/WalkIns.h"

#include <algorithm>
#include <fstream>
#include <map>
#include <set>
#include <sstream>
#include <stdexcept>
#include <string>
#include <tuple>
#include <utility>

#include "avm/io/RunFolder.h"

namespace avm::evaluation
{
namespace
{
/** Two boxes of one person: the run found the person when it has a box this
 *  close to theirs; a first box this close to a box of the frames just
 *  before is a person already in view that the tracker gave a new id (one
 *  stepping out from behind another overlaps them less). */
constexpr double kSameBox = 0.5;
/** The frames before a first box that are looked at: a tenth of a second at
 *  30 Hz, over the detector missing a person on a frame or two. */
constexpr std::size_t kFramesBefore = 3;
/** A person the reference has not found for a second at 30 Hz has left;
 *  WalkIn::framesSeen counts over that second. */
constexpr std::size_t kFramesLost = 30;

struct Box
{
	double x = 0, y = 0, width = 0, height = 0;
	std::optional<unsigned> person;  //!< none when the map placed no person
};
using BoxesByFrame = std::map<std::size_t, std::vector<Box>>;

double iou(const Box& a, const Box& b)
{
	const double w = std::min(a.x + a.width, b.x + b.width) - std::max(a.x, b.x);
	const double h = std::min(a.y + a.height, b.y + b.height) - std::max(a.y, b.y);
	if (w <= 0 || h <= 0) return 0;
	const double both = w * h;
	return both / (a.width * a.height + b.width * b.height - both);
}

BoxesByFrame readBoxes(const std::filesystem::path& run)
{
	const auto file = io::RunFolder(run).detections();
	std::ifstream in(file);
	if (!in) throw std::runtime_error(file.string() + ": cannot be read");
	BoxesByFrame boxes;
	std::string line;
	for (std::size_t number = 1; std::getline(in, line); ++number)
	{
		if (line.empty() || line[0] == '#') continue;
		std::istringstream fields(line);
		std::size_t frame = 0;
		double timestamp = 0, score = 0;
		std::string className, bar;
		Box box;
		if (!(fields >> frame >> timestamp >> className >> score >> box.x >> box.y >> box.width >> box.height >> bar) ||
			bar != "|")
			throw std::runtime_error(file.string() + ":" + std::to_string(number) + ": not a detections.txt line");
		// " | <id> <region>", or why the map placed no person.
		if (unsigned id = 0; fields >> id) box.person = id;
		boxes[frame].push_back(box);
	}
	return boxes;
}

/** A box of the frames just before `frame` that overlaps `box` (kSameBox),
 *  the latest. */
std::optional<std::pair<std::size_t, Box>> sameBoxJustBefore(
	const BoxesByFrame& boxes, std::size_t frame, const Box& box)
{
	for (auto it = boxes.lower_bound(frame); it != boxes.begin();)
	{
		--it;
		if (it->first + kFramesBefore < frame) break;
		for (const auto& earlier : it->second)
			if (iou(earlier, box) >= kSameBox) return std::pair{it->first, earlier};
	}
	return std::nullopt;
}

/** Where the person of a first box of an id walked in: that box, or the
 *  first of the boxes just before it the map placed no person for (too few
 *  depth pixels); nothing when a box just before belongs to another id (the
 *  tracker gave a person in view a new one). */
std::optional<std::pair<std::size_t, Box>> walkedInAt(const BoxesByFrame& boxes, std::size_t frame, Box box)
{
	while (const auto before = sameBoxJustBefore(boxes, frame, box))
	{
		if (before->second.person) return std::nullopt;
		std::tie(frame, box) = *before;
	}
	return std::pair{frame, box};
}

/** The person of a first box, followed through the reference's frames: the
 *  box of their id, or, where the tracker gave them another, the box that
 *  overlaps their last one most (kSameBox at least). Lost when the reference
 *  has not found them for kFramesLost frames. */
class FollowedPerson
{
   public:
	FollowedPerson(const BoxesByFrame& reference, std::size_t frame, const Box& box)
		: m_reference(reference), m_frame(frame), m_box(box)
	{
	}
	/** Their reference box at `frame` (>= the last asked), if the reference
	 *  found them there. */
	std::optional<Box> at(std::size_t frame)
	{
		for (auto it = m_reference.upper_bound(m_frame);
			 it != m_reference.end() && it->first <= frame && it->first <= m_frame + kFramesLost; ++it)
			if (const Box* next = continuation(it->second))
			{
				m_box = *next;
				m_frame = it->first;
			}
		return m_frame == frame ? std::optional<Box>(m_box) : std::nullopt;
	}

   private:
	const Box* continuation(const std::vector<Box>& boxes) const
	{
		const Box* best = nullptr;
		for (const auto& b : boxes)
		{
			if (b.person && b.person == m_box.person) return &b;
			if (iou(b, m_box) >= kSameBox && (!best || iou(b, m_box) > iou(*best, m_box))) best = &b;
		}
		return best;
	}

	const BoxesByFrame& m_reference;
	std::size_t m_frame;
	Box m_box;
};
}  // namespace

std::vector<WalkIn> walkInsFound(const std::filesystem::path& run, const std::filesystem::path& reference)
{
	const BoxesByFrame found = readBoxes(run), truth = readBoxes(reference);
	std::vector<WalkIn> walkIns;
	std::set<unsigned> ids;
	for (const auto& [firstFrame, boxes] : truth)
		for (const auto& firstBox : boxes)
		{
			if (!firstBox.person || !ids.insert(*firstBox.person).second) continue;
			const auto start = walkedInAt(truth, firstFrame, firstBox);
			if (!start) continue;
			const std::size_t frame = start->first;
			Box box = start->second;
			box.person = firstBox.person;
			WalkIn w{frame, *firstBox.person, 1, std::nullopt};
			FollowedPerson counted(truth, frame, box);
			for (auto it = truth.upper_bound(frame); it != truth.end() && it->first < frame + kFramesLost; ++it)
				w.framesSeen += counted.at(it->first).has_value();
			FollowedPerson person(truth, frame, box);
			for (auto it = found.lower_bound(frame); it != found.end() && !w.foundAt; ++it)
				if (const auto theirs = person.at(it->first))
					for (const auto& b : it->second)
						if (iou(b, *theirs) >= kSameBox) w.foundAt = it->first;
			walkIns.push_back(w);
		}
	std::stable_sort(
		walkIns.begin(), walkIns.end(), [](const WalkIn& a, const WalkIn& b) { return a.frame < b.frame; });
	return walkIns;
}
}  // namespace avm::evaluation
