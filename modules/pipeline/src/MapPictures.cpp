#include "avm/persons/PersonColour.h"
#include "avm/pipeline/MapPictures.h"

#include <mrpt/math/geometry.h>
#include <mrpt/poses/CPose3D.h>

#include <algorithm>
#include <cmath>
#include <functional>
#include <utility>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>

#include "avm/io/AtomicFile.h"
#include "avm/maps/MapColours.h"

namespace avm::pipeline
{
namespace
{
cv::Scalar bgr(const mrpt::img::TColor& c) { return cv::Scalar(c.B, c.G, c.R); }

// The map's own colours (avm/maps/MapColours.h), as in map.3Dscene and the live view.
const cv::Scalar kBackground(255, 255, 255), kText(30, 30, 30);
const cv::Scalar kLow = bgr(kLowColour), kHigh = bgr(kHighColour), kRegion = bgr(kRegionColour);
const cv::Scalar kTrajectory = bgr(kTrajectoryColour), kPerson = bgr(persons::kPersonColour);

/** A person's marker: a dot and the id beside it. */
void drawPerson(cv::Mat& img, const cv::Point2d& at, std::uint32_t id)
{
	cv::circle(img, at, 7, kPerson, cv::FILLED, cv::LINE_AA);
	cv::circle(img, at, 7, cv::Scalar(255, 255, 255), 1, cv::LINE_AA);
	// Outlined in white: the id stays readable over the person's own shape.
	for (const auto& [colour, thickness] : {std::pair{cv::Scalar(255, 255, 255), 5}, {kPerson, 2}})
		cv::putText(img, std::to_string(id), at + cv::Point2d(9, -6), cv::FONT_HERSHEY_SIMPLEX, 0.6, colour, thickness,
			cv::LINE_AA);
}

/** Colour of a voxel: its tree's colour, darker low down and full at the top,
 *  so the structure reads in a flat picture. */
cv::Scalar voxelColour(const PictureVoxel& v, float zMin, float zMax)
{
	const double t = zMax > zMin ? std::clamp((v.centre.z - zMin) / (zMax - zMin), 0.f, 1.f) : 0.5;
	return (v.highResolution ? kHigh : kLow) * (0.45 + 0.55 * t);
}

void save(const cv::Mat& img, const std::filesystem::path& png)
{
	io::writeFileAtomically(png,
		[&](const std::filesystem::path& tmp)
		{
			if (!cv::imwrite(tmp.string(), img)) throw std::runtime_error(png.string() + ": cannot write picture");
		});
}

void drawLegend(cv::Mat& img, const MapPictureContent& c, const std::string& title)
{
	std::size_t low = 0, high = 0;
	for (const auto& v : c.voxels) (v.highResolution ? high : low)++;
	const auto line = [&](int row, const std::string& text, const cv::Scalar& colour) {
		cv::putText(img, text, {12, 24 + 22 * row}, cv::FONT_HERSHEY_SIMPLEX, 0.55, colour, 1, cv::LINE_AA);
	};
	char buf[128];
	line(0, title, kText);
	std::snprintf(buf, sizeof(buf), "low %.2f m: %zu occupied voxels", c.lowResolution, low);
	line(1, buf, kLow);
	std::snprintf(buf, sizeof(buf), "high %.2f m: %zu occupied voxels", c.highResolution, high);
	line(2, buf, kHigh);
	line(3, "camera trajectory", kTrajectory);
	if (!c.regions.empty()) line(4, "high-resolution regions", kRegion);
	if (!c.persons.empty()) line(5, "persons: id at the last position, last shape", kPerson);
}

std::pair<float, float> heightRange(const std::vector<PictureVoxel>& voxels)
{
	if (voxels.empty()) return {0.f, 1.f};
	const auto [lo, hi] = std::minmax_element(
		voxels.begin(), voxels.end(), [](const auto& a, const auto& b) { return a.centre.z < b.centre.z; });
	return {lo->centre.z, hi->centre.z};
}
/** The persons' shapes in a perspective view whose projection is `project`
 *  (focal length `f` [px]), over the map (the map may hold a still person
 *  at the same voxels), far to near. */
void drawShapesInPerspective(cv::Mat& img, const MapPictureContent& c,
	const std::function<bool(const mrpt::math::TPoint3D&, cv::Point2d&, double&)>& project, double f)
{
	std::vector<std::pair<double, cv::Point2d>> shape;
	for (const auto& person : c.persons)
		for (const auto& v : person.shape)
		{
			cv::Point2d px;
			double depth = 0;
			if (project(mrpt::math::TPoint3D(v), px, depth)) shape.emplace_back(depth, px);
		}
	std::sort(shape.begin(), shape.end(), [](const auto& a, const auto& b) { return a.first > b.first; });
	for (const auto& [depth, px] : shape)
	{
		const double half = std::max(0.5, 0.5 * f * c.highResolution / depth);
		cv::rectangle(img, px - cv::Point2d(half, half), px + cv::Point2d(half, half), kPerson, cv::FILLED);
	}
}
}  // namespace

void drawTopView(const MapPictureContent& c, const std::filesystem::path& png, int sizePx)
{
	mrpt::math::TBoundingBox box({0, 0, 0}, {0, 0, 0});
	bool first = true;
	const auto extend = [&](double x, double y)
	{
		if (first) box = mrpt::math::TBoundingBox({x, y, 0}, {x, y, 0}), first = false;
		box.updateWithPoint({x, y, 0});
	};
	for (const auto& v : c.voxels) extend(v.centre.x, v.centre.y);
	for (const auto& p : c.trajectory) extend(p.pose.x(), p.pose.y());
	const double margin = 0.5;
	const double span = std::max(box.max.x - box.min.x, box.max.y - box.min.y) + 2 * margin;
	const double scale = sizePx / std::max(span, 1e-3);  // px per metre
	const auto toPx = [&](double x, double y)
	{ return cv::Point2d((x - box.min.x + margin) * scale, sizePx - (y - box.min.y + margin) * scale); };

	cv::Mat img(sizePx, sizePx, CV_8UC3, kBackground);
	std::vector<const PictureVoxel*> order;
	for (const auto& v : c.voxels) order.push_back(&v);
	std::sort(order.begin(), order.end(), [](auto* a, auto* b) { return a->centre.z < b->centre.z; });
	const auto [zMin, zMax] = heightRange(c.voxels);
	for (const auto* v : order)
	{
		const double half = std::max(0.5, 0.5 * v->size * scale);
		const auto p = toPx(v->centre.x, v->centre.y);
		cv::rectangle(img, cv::Point2d(p.x - half, p.y - half), cv::Point2d(p.x + half, p.y + half),
			voxelColour(*v, zMin, zMax), cv::FILLED);
	}
	for (const auto& r : c.regions)
		cv::rectangle(img, toPx(r.min.x, r.min.y), toPx(r.max.x, r.max.y), kRegion, 2, cv::LINE_AA);
	for (std::size_t i = 1; i < c.trajectory.size(); ++i)
		cv::line(img, toPx(c.trajectory[i - 1].pose.x(), c.trajectory[i - 1].pose.y()),
			toPx(c.trajectory[i].pose.x(), c.trajectory[i].pose.y()), kTrajectory, 2, cv::LINE_AA);
	if (!c.trajectory.empty())
		cv::circle(img, toPx(c.trajectory.front().pose.x(), c.trajectory.front().pose.y()), 5, kTrajectory, cv::FILLED);
	const double shapeHalf = std::max(0.5, 0.5 * c.highResolution * scale);
	for (const auto& p : c.persons)
		for (const auto& v : p.shape)
		{
			const auto at = toPx(v.x, v.y);
			cv::rectangle(img, at - cv::Point2d(shapeHalf, shapeHalf), at + cv::Point2d(shapeHalf, shapeHalf), kPerson,
				cv::FILLED);
		}
	for (const auto& p : c.persons) drawPerson(img, toPx(p.position.x, p.position.y), p.id);
	// 1 m scale bar
	cv::line(img, {12, sizePx - 20}, {12 + static_cast<int>(scale), sizePx - 20}, kText, 2);
	cv::putText(img, "1 m", {12, sizePx - 28}, cv::FONT_HERSHEY_SIMPLEX, 0.5, kText, 1, cv::LINE_AA);
	drawLegend(img, c, "top view (world XY)");
	save(img, png);
}

void drawPerspectiveView(const MapPictureContent& c, const std::filesystem::path& png, int sizePx)
{
	if (c.voxels.empty() && c.trajectory.empty())
	{
		cv::Mat img(sizePx * 3 / 4, sizePx, CV_8UC3, kBackground);
		drawLegend(img, c, "perspective view (empty map)");
		save(img, png);
		return;
	}
	// Look at the centroid of the map from behind the first camera, raised.
	mrpt::math::TPoint3D centre(0, 0, 0);
	for (const auto& v : c.voxels) centre += mrpt::math::TPoint3D(v.centre);
	if (!c.voxels.empty()) centre *= 1.0 / double(c.voxels.size());
	double radius = 1.0;
	for (const auto& v : c.voxels) radius = std::max(radius, (mrpt::math::TPoint3D(v.centre) - centre).norm());
	mrpt::math::TPoint3D start = c.trajectory.empty() ? centre + mrpt::math::TPoint3D(-1, 0, 0)
													  : mrpt::math::TPoint3D(c.trajectory.front().pose.translation());
	mrpt::math::TPoint3D back = start - centre;
	back.z = 0;
	if (back.norm() < 1e-6) back = {-1, 0, 0};
	back *= 1.0 / back.norm();
	const double distance = 1.6 * radius;
	const mrpt::math::TPoint3D eye =
		centre + back * (distance * std::cos(0.6)) + mrpt::math::TPoint3D(0, 0, distance * std::sin(0.6));
	// Camera axes: forward to the centre, right, down (optical convention).
	mrpt::math::TPoint3D fwd = centre - eye;
	fwd *= 1.0 / fwd.norm();
	mrpt::math::TPoint3D right, down;
	mrpt::math::crossProduct3D(fwd, mrpt::math::TPoint3D(0, 0, 1), right);
	right *= 1.0 / right.norm();
	mrpt::math::crossProduct3D(fwd, right, down);

	const int w = sizePx, h = sizePx * 3 / 4;
	const double f = 0.9 * w;
	struct Projected
	{
		cv::Point2d px;
		double depth;
		double halfPx;
		cv::Scalar colour;
	};
	const auto project = [&](const mrpt::math::TPoint3D& p, cv::Point2d& px, double& depth)
	{
		const auto d = p - eye;
		depth = d.x * fwd.x + d.y * fwd.y + d.z * fwd.z;
		if (depth < 0.1) return false;
		px = {w / 2.0 + f * (d.x * right.x + d.y * right.y + d.z * right.z) / depth,
			h / 2.0 + f * (d.x * down.x + d.y * down.y + d.z * down.z) / depth};
		return true;
	};
	const auto [zMin, zMax] = heightRange(c.voxels);
	std::vector<Projected> items;
	items.reserve(c.voxels.size());
	for (const auto& v : c.voxels)
	{
		Projected p;
		if (!project(mrpt::math::TPoint3D(v.centre), p.px, p.depth)) continue;
		p.halfPx = std::max(0.5, 0.5 * f * v.size / p.depth);
		p.colour = voxelColour(v, zMin, zMax);
		items.push_back(p);
	}
	std::sort(items.begin(), items.end(), [](const auto& a, const auto& b) { return a.depth > b.depth; });
	cv::Mat img(h, w, CV_8UC3, kBackground);
	for (const auto& p : items)
	{
		const cv::Point2d a(p.px.x - p.halfPx, p.px.y - p.halfPx), b(p.px.x + p.halfPx, p.px.y + p.halfPx);
		cv::rectangle(img, a, b, p.colour, cv::FILLED);
		cv::rectangle(img, a, b, p.colour * 0.7, 1);
	}
	cv::Point2d prev;
	double depth;
	bool havePrev = false;
	for (const auto& tp : c.trajectory)
	{
		cv::Point2d px;
		const bool ok = project(mrpt::math::TPoint3D(tp.pose.translation()), px, depth);
		if (ok && havePrev) cv::line(img, prev, px, kTrajectory, 3, cv::LINE_AA);
		prev = px;
		havePrev = ok;
	}
	drawShapesInPerspective(img, c, project, f);
	for (const auto& person : c.persons)
	{
		cv::Point2d px;
		if (project(person.position, px, depth)) drawPerson(img, px, person.id);
	}
	drawLegend(img, c, "perspective view");
	save(img, png);
}
}  // namespace avm::pipeline
