// .bt files as OctoMap users get them: octomap::OcTree::writeBinary turns the
// tree into its maximum-likelihood form and prunes it before writing, which
// octovis and octomap_server users expect (and which is a third smaller than
// the tree as stored). writeBinary does that to the tree it writes, and the
// liboctomap Debian ships prints " done." on stderr each time; these write the
// same bytes from a const tree, which keeps its log-odds, and print nothing.
#pragma once

#include <filesystem>
#include <iosfwd>
#include <memory>
#include <string>

namespace octomap
{
class OcTree;
}

namespace avm
{
/** The bytes `octomap::OcTree::writeBinary` writes for a copy of `tree`. */
std::string binaryTreeBytes(const octomap::OcTree& tree);

/** binaryTreeBytes() into `file`, atomically (io::writeFileAtomically);
 *  throws naming the file when it cannot be written. */
void writeBinaryTree(const octomap::OcTree& tree, const std::filesystem::path& file);

/** A .bt file read back (as `octomap::OcTree::readBinary`, which also talks on
 *  stderr); throws naming the file when it is missing or not an OcTree. */
std::unique_ptr<octomap::OcTree> readBinaryTree(const std::filesystem::path& file);
}  // namespace avm
