/* A small stand-in for <windows.h> on systems that have none (Linux, macOS): only the
 * types and calling-convention words that code written for the vendor's Windows motion
 * library uses, so such code compiles with `-I` pointing here and no other change.
 * It is not the Windows API; on Windows the compiler's own <windows.h> is used instead. */
#ifndef MAXK_WINDOWS_COMPAT_H
#define MAXK_WINDOWS_COMPAT_H

#if defined(_WIN32)
#include_next <windows.h>
#else

#include <stddef.h>
#include <stdint.h>
#include <string.h>
#include <strings.h>
#include <time.h>
#include <unistd.h>

typedef void *HANDLE;
typedef HANDLE *PHANDLE;
typedef char *LPSTR;
typedef const char *LPCSTR;
typedef char CHAR;
typedef char TCHAR;
typedef TCHAR *LPTSTR;
typedef const TCHAR *LPCTSTR;
typedef int BOOL;
typedef int INT;
typedef unsigned int UINT;
typedef unsigned char BYTE;
typedef unsigned short WORD;
typedef uint32_t DWORD;
typedef long LONG;
typedef unsigned long ULONG;
typedef LONG *PLONG;
typedef LONG *LPLONG;
typedef DWORD *LPDWORD;
typedef void VOID;
typedef void *LPVOID;
typedef short SHORT;
typedef float FLOAT;
typedef double DOUBLE;

#ifndef TRUE
#define TRUE 1
#endif
#ifndef FALSE
#define FALSE 0
#endif
#ifndef NULL
#define NULL ((void *)0)
#endif
#define INVALID_HANDLE_VALUE ((HANDLE)(intptr_t)-1)
#define MAX_PATH 260

/* Calling conventions and import/export words mean nothing on these systems. */
#define _stdcall
#define __stdcall
#define _cdecl
#define __cdecl
#define WINAPI
#define APIENTRY
#define CALLBACK
#define PASCAL
#define __declspec(x)
#define _TEXT(s) s
#define TEXT(s) s
#define _T(s) s

/* Helpers legacy programs lean on. */
#define Sleep(ms) usleep((useconds_t)(ms) * 1000u)
#define ZeroMemory(p, n) memset((p), 0, (n))
#define lstrlen(s) ((int)strlen(s))
#define lstrcpy(d, s) strcpy((d), (s))
#define lstrcat(d, s) strcat((d), (s))
#define lstrcmp(a, b) strcmp((a), (b))
#define _strnicmp strncasecmp
#define _stricmp strcasecmp
#define stricmp strcasecmp
#define strnicmp strncasecmp

static inline DWORD GetTickCount(void)
{
    struct timespec now;
    clock_gettime(CLOCK_MONOTONIC, &now);
    return (DWORD)((uint64_t)now.tv_sec * 1000u + (uint64_t)now.tv_nsec / 1000000u);
}

#endif /* _WIN32 */
#endif /* MAXK_WINDOWS_COMPAT_H */
