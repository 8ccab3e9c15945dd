/* cairn: which symbols the shared libraries export. The library is built with hidden visibility
 * (-fvisibility=hidden); only declarations marked CN_API form its interface. */
#ifndef CAIRN_EXPORT_H
#define CAIRN_EXPORT_H

#if defined(_WIN32) || defined(__CYGWIN__)
#define CN_API
#else
#define CN_API __attribute__((visibility("default")))
#endif

#endif
