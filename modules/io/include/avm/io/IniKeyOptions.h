// An MRPT options struct (CLoadableOptions) whose keys are declared once, in
// its `iniKeys()` (avm/io/IniKeys.h): loading, saving and validation all come
// from that list, so no options struct writes them again.
//
//   struct TMyOptions : public io::CIniKeyOptions<TMyOptions>
//   {
//       double gain = 1;
//       static io::IniKeys<TMyOptions> iniKeys();
//   };
//
// The methods are defined in IniKeys.h; the .cpp that defines iniKeys()
// instantiates them: `template struct avm::io::CIniKeyOptions<TMyOptions>;`.
#pragma once

#include <mrpt/config/CLoadableOptions.h>

#include <string>
#include <vector>

namespace avm::io
{
template <class Options>
class IniKeys;

/** What unknownKeys() asks of options of any type: the earlier names of
 *  keys that they still read (IniKeys::renamed). */
struct CIniKeyNames : public mrpt::config::CLoadableOptions
{
	virtual std::vector<std::string> oldKeyNames() const = 0;
};

template <class Options>
struct CIniKeyOptions : public CIniKeyNames
{
	/** Reads the keys present in [section] (absent ones keep their value),
	 *  then validates. Throws std::invalid_argument "[section] key = value: why". */
	void loadFromConfigFile(const mrpt::config::CConfigFileBase& source, const std::string& section) override;
	/** Writes every key, as loadFromConfigFile reads it back. */
	void saveToConfigFile(mrpt::config::CConfigFileBase& target, const std::string& section) const override;
	/** Throws std::invalid_argument "[section] key = value: why" for the first failed check. */
	void validate(const std::string& section) const;
	std::vector<std::string> oldKeyNames() const override;
};
}  // namespace avm::io
