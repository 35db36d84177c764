#pragma once
// The MIT (Expat) licence notice that every copy of an embedded JavaScript library
// (Chart.js in reports, three.js in the trainer page) carries, as a leading comment.
#include <string>
#include <string_view>

namespace needlesim {

// "/*! <what>\nCopyright (c) <copyright>. MIT (Expat) licence:\n<the licence> */\n"
inline std::string expatNotice(std::string_view what, std::string_view copyright) {
  return "/*! " + std::string(what) + "\nCopyright (c) " + std::string(copyright) +
         ". MIT (Expat) licence:\n"
         "Permission is hereby granted, free of charge, to any person obtaining a copy of this software and\n"
         "associated documentation files (the \"Software\"), to deal in the Software without restriction,\n"
         "including without limitation the rights to use, copy, modify, merge, publish, distribute, sublicense,\n"
         "and/or sell copies of the Software, and to permit persons to whom the Software is furnished to do so,\n"
         "subject to the following conditions: The above copyright notice and this permission notice shall be\n"
         "included in all copies or substantial portions of the Software. THE SOFTWARE IS PROVIDED \"AS IS\",\n"
         "WITHOUT WARRANTY OF ANY KIND, EXPRESS OR IMPLIED, INCLUDING BUT NOT LIMITED TO THE WARRANTIES OF\n"
         "MERCHANTABILITY, FITNESS FOR A PARTICULAR PURPOSE AND NONINFRINGEMENT. IN NO EVENT SHALL THE AUTHORS OR\n"
         "COPYRIGHT HOLDERS BE LIABLE FOR ANY CLAIM, DAMAGES OR OTHER LIABILITY, WHETHER IN AN ACTION OF CONTRACT,\n"
         "TORT OR OTHERWISE, ARISING FROM, OUT OF OR IN CONNECTION WITH THE SOFTWARE OR THE USE OR OTHER DEALINGS\n"
         "IN THE SOFTWARE. */\n";
}

}  // namespace needlesim
