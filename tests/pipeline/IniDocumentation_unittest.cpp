// ini/default.ini documents every key avm-map reads as the options structs
// declare it (io::IniKeys): each declared key is in the file with the comment
// "// description [unit] (default X)" that its declaration gives, X the
// built-in default, at that default, and the file holds no key the code does
// not read. The other ini files of avm-map hold only what differs from it.
#include <gtest/gtest.h>
#include <mrpt/config/CConfigFile.h>
#include <mrpt/config/CConfigFileMemory.h>

#include <algorithm>
#include <fstream>
#include <map>
#include <string>

#include "avm/detection/TDetectorOptions.h"
#include "avm/io/IniKeys.h"
#include "avm/plugin/CAdaptiveOctoMap.h"
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

/** Each key `declared` is in [section] of default.ini with the comment its
 *  declaration gives; [section] holds no other key. */
void expectDocumented(const IniComments& docs, const mrpt::config::CConfigFileBase& ini, const std::string& section,
	const std::vector<io::IniKeyDoc>& declared)
{
	ASSERT_FALSE(declared.empty()) << section;
	const auto inSection = docs.find(section);
	ASSERT_NE(inSection, docs.end()) << "ini/default.ini has no [" << section << "]";
	for (const auto& key : declared)
	{
		const auto line = inSection->second.find(key.key);
		if (line == inSection->second.end())
			ADD_FAILURE() << "ini/default.ini does not document [" << section << "] " << key.key << "; its line:\n"
						  << key.key << " = " << key.defaultText << "  // " << key.comment();
		else
			EXPECT_EQ(line->second, key.comment())
				<< "[" << section << "] " << key.key << ": the comment in ini/default.ini is not the declaration's";
	}
	std::vector<std::string> present;
	ini.getAllKeys(section, present);
	for (const auto& key : present)
		if (std::none_of(declared.begin(), declared.end(), [&](const io::IniKeyDoc& d) { return d.key == key; }))
			ADD_FAILURE() << "ini/default.ini has [" << section << "] " << key << ", which avm-map does not read";
}

/** The value of each key of [section] as `options`, loaded from `ini`, write
 *  it back: the struct's own spelling (0.20 and 0.2 alike), by key. */
template <class Options>
std::map<std::string, std::string> savedValues(const mrpt::config::CConfigFileBase& ini, const std::string& section)
{
	Options options;
	options.loadFromConfigFile(ini, section);
	mrpt::config::CConfigFileMemory saved;
	options.saveToConfigFile(saved, section);
	std::vector<std::string> keys;
	saved.getAllKeys(section, keys);
	std::map<std::string, std::string> values;
	for (const auto& key : keys) values[key] = saved.read_string(section, key, "");
	return values;
}

/** [section] of `file` as `Options`: in ini/default.ini every key at its
 *  built-in default; in any other file, each key it sets away from it. */
template <class Options>
void expectValues(const fs::path& file, const std::string& section)
{
	const mrpt::config::CConfigFile ini(file.string());
	const auto values = savedValues<Options>(ini, section);
	const auto builtIn = savedValues<Options>(mrpt::config::CConfigFileMemory(), section);
	const bool isDefaultIni = file.filename() == "default.ini";
	std::vector<std::string> present;
	ini.getAllKeys(section, present);
	for (const auto& key : present)
	{
		const auto value = values.find(key), defaultValue = builtIn.find(key);
		if (value == values.end()) continue;  // another struct's key of a shared section
		ASSERT_NE(defaultValue, builtIn.end()) << key;
		if (isDefaultIni)
			EXPECT_EQ(value->second, defaultValue->second)
				<< file << " [" << section << "] " << key << " is not at its built-in default";
		else
			EXPECT_NE(value->second, defaultValue->second)
				<< file << " [" << section << "] " << key << " = its built-in default: leave it to the default";
	}
}

/** expectValues for every section of avm-map's options in `file`. */
void expectValuesOfEverySection(const fs::path& file)
{
	const std::string prefix = "map_adaptiveOctoMap_00_";
	expectValues<pipeline::TPipelineOptions>(file, "pipeline");
	expectValues<odometry::TOdometryOptions>(file, "odometry");
	expectValues<detection::TDetectorOptions>(file, "detection");
	expectValues<CAdaptiveOctoMap::TCreationOptions>(file, prefix + "creationOpts");
	expectValues<CAdaptiveOctoMap::TInsertionOptions>(file, prefix + "insertOpts");
	expectValues<persons::TPersonLayerOptions>(file, prefix + "insertOpts");
	expectValues<CAdaptiveOctoMap::TLikelihoodOptions>(file, prefix + "likelihoodOpts");
	expectValues<CAdaptiveOctoMap::TRenderingOptions>(file, prefix + "renderOpts");
}
}  // namespace

TEST(IniDocumentation, DefaultIniDocumentsEveryKeyWithItsDefault)
{
	const fs::path file = fs::path(AVM_SOURCE_DIR) / "ini/default.ini";
	const auto docs = commentsOf(file);
	mrpt::config::CConfigFile ini(file.string());
	const auto of = [](const auto& options) { return options.iniKeys().documentation(options); };
	expectDocumented(docs, ini, "pipeline", of(pipeline::TPipelineOptions()));
	expectDocumented(docs, ini, "odometry", of(odometry::TOdometryOptions()));
	expectDocumented(docs, ini, "detection", of(detection::TDetectorOptions()));
	const CAdaptiveOctoMap map;
	const std::string prefix = "map_adaptiveOctoMap_00_";
	expectDocumented(docs, ini, prefix + "creationOpts", of(map.creationOptions()));
	// The map's and the person layer's keys share the section.
	auto insertKeys = of(map.insertionOptions);
	const auto personKeys = of(map.personOptions);
	insertKeys.insert(insertKeys.end(), personKeys.begin(), personKeys.end());
	expectDocumented(docs, ini, prefix + "insertOpts", insertKeys);
	expectDocumented(docs, ini, prefix + "likelihoodOpts", of(map.likelihoodOptions));
	expectDocumented(docs, ini, prefix + "renderOpts", of(map.renderingOptions));
}

TEST(IniDocumentation, DefaultIniHoldsTheBuiltInDefaults)
{
	// avm-map with ini/default.ini, a program or stock MRPT app with no ini,
	// and an ini that leaves a key out all get the same value for it.
	expectValuesOfEverySection(fs::path(AVM_SOURCE_DIR) / "ini/default.ini");
}

TEST(IniDocumentation, TheOtherIniFilesHoldOnlyWhatDiffersFromTheDefaults)
{
	for (const char* name : {"paper.ini", "detect.ini", "detect-on-change.ini", "odometry.ini", "small-computer.ini"})
		expectValuesOfEverySection(fs::path(AVM_SOURCE_DIR) / "ini" / name);
}
