// ini/default.ini documents every key avm-map reads: each key an options
// struct writes back (saveToConfigFile writes exactly the keys it reads) is in
// the file with a "// ... (default X)" comment whose X is the built-in
// default, and the file holds no key the code does not read.
#include <gtest/gtest.h>
#include <mrpt/config/CConfigFileMemory.h>

#include <cstdlib>
#include <fstream>
#include <map>
#include <optional>
#include <string>

#include "avm/detection/TDetectorOptions.h"
#include "avm/io/IniOptions.h"
#include "avm/maps/CAdaptiveOctoMap.h"
#include "avm/odometry/TOdometryOptions.h"
#include "avm/pipeline/MappingPipeline.h"

namespace fs = std::filesystem;
using namespace avm;

namespace
{
std::string trim(const std::string& s)
{
	const auto b = s.find_first_not_of(" \t\r");
	if (b == std::string::npos) return {};
	return s.substr(b, s.find_last_not_of(" \t\r") - b + 1);
}

/** The comment after "//" of every "key = value // comment" line, by section and key. */
using IniComments = std::map<std::string, std::map<std::string, std::string>>;

IniComments commentsOf(const fs::path& file)
{
	std::ifstream in(file);
	EXPECT_TRUE(in.good()) << file;
	IniComments out;
	std::string section;
	for (std::string line; std::getline(in, line);)
	{
		line = trim(line);
		if (line.empty() || line[0] == '#' || line[0] == ';') continue;
		if (line[0] == '[')
		{
			section = line.substr(1, line.find(']') - 1);
			continue;
		}
		const auto equals = line.find('='), slashes = line.find("//");
		if (equals == std::string::npos) continue;
		out[section][trim(line.substr(0, equals))] =
			slashes == std::string::npos ? std::string() : trim(line.substr(slashes + 2));
	}
	return out;
}

/** "X" of a comment ending in "(default X)"; nothing without one. */
std::optional<std::string> documentedDefault(const std::string& comment)
{
	const std::string tag = "(default ";
	const auto at = comment.rfind(tag);
	if (at == std::string::npos || comment.back() != ')') return std::nullopt;
	return trim(comment.substr(at + tag.size(), comment.size() - at - tag.size() - 1));
}

bool sameValue(const std::string& documented, const std::string& builtIn)
{
	if (documented == builtIn) return true;
	char* endA = nullptr;
	char* endB = nullptr;
	const double a = std::strtod(documented.c_str(), &endA), b = std::strtod(builtIn.c_str(), &endB);
	return endA != documented.c_str() && *endA == 0 && endB != builtIn.c_str() && *endB == 0 && a == b;
}

void expectDocumented(
	const IniComments& docs, const mrpt::config::CConfigFileBase& ini, const std::string& section,
	const mrpt::config::CLoadableOptions& options)
{
	mrpt::config::CConfigFileMemory defaults;
	options.saveToConfigFile(defaults, section);
	std::vector<std::string> keys;
	defaults.getAllKeys(section, keys);
	ASSERT_FALSE(keys.empty()) << section;
	const auto inSection = docs.find(section);
	ASSERT_NE(inSection, docs.end()) << "ini/default.ini has no [" << section << "]";
	for (const auto& key : keys)
	{
		const auto line = inSection->second.find(key);
		if (line == inSection->second.end())
		{
			ADD_FAILURE() << "ini/default.ini does not document [" << section << "] " << key;
			continue;
		}
		const auto documented = documentedDefault(line->second);
		if (!documented)
		{
			ADD_FAILURE() << "[" << section << "] " << key << ": the comment does not end in (default X): "
						  << line->second;
			continue;
		}
		const std::string builtIn = trim(defaults.read_string(section, key, ""));
		EXPECT_TRUE(sameValue(*documented, builtIn))
			<< "[" << section << "] " << key << ": documented default " << *documented << ", built-in " << builtIn;
	}
	for (const auto& key : io::unknownKeys(ini, section, options))
		ADD_FAILURE() << "ini/default.ini has [" << section << "] " << key << ", which avm-map does not read";
}
}  // namespace

TEST(IniDocumentation, DefaultIniDocumentsEveryKeyWithItsDefault)
{
	const fs::path file = fs::path(AVM_SOURCE_DIR) / "ini/default.ini";
	const auto docs = commentsOf(file);
	mrpt::config::CConfigFile ini(file.string());
	expectDocumented(docs, ini, "pipeline", pipeline::TPipelineOptions());
	expectDocumented(docs, ini, "odometry", odometry::TOdometryOptions());
	expectDocumented(docs, ini, "detection", detection::TDetectorOptions());
	const CAdaptiveOctoMap map;
	const std::string prefix = "map_adaptiveOctoMap_00_";
	expectDocumented(docs, ini, prefix + "creationOpts", map.creationOptions());
	expectDocumented(docs, ini, prefix + "insertOpts", map.insertionOptions);
	expectDocumented(docs, ini, prefix + "likelihoodOpts", map.likelihoodOptions);
	expectDocumented(docs, ini, prefix + "renderOpts", map.renderingOptions);
}
