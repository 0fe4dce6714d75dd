/* OpenGL and EGL through libepoxy, loaded when the first context is made (render_gl_load()):
 * neither sinew nor libsinew links libepoxy, so that a program that never draws (sinew --help,
 * sinew info) does not load it and its thousands of relocations (a millisecond of every start).
 *
 * Include this instead of <epoxy/gl.h> and <epoxy/egl.h>. Each gl and egl function is a
 * function pointer in libepoxy (epoxy_glBindBuffer ...); each name below is made a macro for
 * that pointer, found by dlsym. A function not listed is refused by the linker: add it here. */
#ifndef SINEW_RENDER_GL_H
#define SINEW_RENDER_GL_H

#include <stdbool.h>
#include <stddef.h>

#include <epoxy/egl.h>
#include <epoxy/gl.h>

#define RENDER_GL_POINTERS(X)                                                                                          \
    X(epoxy_eglBindAPI)                                                                                                \
    X(epoxy_eglChooseConfig)                                                                                           \
    X(epoxy_eglCreateContext)                                                                                          \
    X(epoxy_eglDestroyContext)                                                                                         \
    X(epoxy_eglGetDisplay)                                                                                             \
    X(epoxy_eglGetError)                                                                                               \
    X(epoxy_eglGetPlatformDisplayEXT)                                                                                  \
    X(epoxy_eglInitialize)                                                                                             \
    X(epoxy_eglMakeCurrent)                                                                                            \
    X(epoxy_eglQueryDevicesEXT)                                                                                        \
    X(epoxy_eglQueryString)                                                                                            \
    X(epoxy_eglReleaseThread)                                                                                          \
    X(epoxy_eglTerminate)                                                                                              \
    X(epoxy_glActiveTexture)                                                                                           \
    X(epoxy_glAttachShader)                                                                                            \
    X(epoxy_glBindBuffer)                                                                                              \
    X(epoxy_glBindFramebuffer)                                                                                         \
    X(epoxy_glBindRenderbuffer)                                                                                        \
    X(epoxy_glBindTexture)                                                                                             \
    X(epoxy_glBindVertexArray)                                                                                         \
    X(epoxy_glBlendFuncSeparate)                                                                                       \
    X(epoxy_glBlitFramebuffer)                                                                                         \
    X(epoxy_glBufferData)                                                                                              \
    X(epoxy_glBufferSubData)                                                                                           \
    X(epoxy_glCheckFramebufferStatus)                                                                                  \
    X(epoxy_glClear)                                                                                                   \
    X(epoxy_glClearColor)                                                                                              \
    X(epoxy_glClearDepth)                                                                                              \
    X(epoxy_glCompileShader)                                                                                           \
    X(epoxy_glCreateProgram)                                                                                           \
    X(epoxy_glCreateShader)                                                                                            \
    X(epoxy_glDeleteBuffers)                                                                                           \
    X(epoxy_glDeleteFramebuffers)                                                                                      \
    X(epoxy_glDeleteProgram)                                                                                           \
    X(epoxy_glDeleteRenderbuffers)                                                                                     \
    X(epoxy_glDeleteShader)                                                                                            \
    X(epoxy_glDeleteTextures)                                                                                          \
    X(epoxy_glDeleteVertexArrays)                                                                                      \
    X(epoxy_glDepthFunc)                                                                                               \
    X(epoxy_glDepthMask)                                                                                               \
    X(epoxy_glDisable)                                                                                                 \
    X(epoxy_glDrawArrays)                                                                                              \
    X(epoxy_glDrawBuffer)                                                                                              \
    X(epoxy_glDrawElements)                                                                                            \
    X(epoxy_glDrawElementsBaseVertex)                                                                                  \
    X(epoxy_glDrawElementsInstanced)                                                                                   \
    X(epoxy_glEnable)                                                                                                  \
    X(epoxy_glEnableVertexAttribArray)                                                                                 \
    X(epoxy_glFinish)                                                                                                  \
    X(epoxy_glFramebufferRenderbuffer)                                                                                 \
    X(epoxy_glFramebufferTexture2D)                                                                                    \
    X(epoxy_glGenBuffers)                                                                                              \
    X(epoxy_glGenFramebuffers)                                                                                         \
    X(epoxy_glGenRenderbuffers)                                                                                        \
    X(epoxy_glGenTextures)                                                                                             \
    X(epoxy_glGenVertexArrays)                                                                                         \
    X(epoxy_glGenerateMipmap)                                                                                          \
    X(epoxy_glGetError)                                                                                                \
    X(epoxy_glGetIntegerv)                                                                                             \
    X(epoxy_glGetProgramInfoLog)                                                                                       \
    X(epoxy_glGetProgramiv)                                                                                            \
    X(epoxy_glGetShaderInfoLog)                                                                                        \
    X(epoxy_glGetShaderiv)                                                                                             \
    X(epoxy_glGetString)                                                                                               \
    X(epoxy_glGetUniformLocation)                                                                                      \
    X(epoxy_glLinkProgram)                                                                                             \
    X(epoxy_glMapBufferRange)                                                                                          \
    X(epoxy_glPixelStorei)                                                                                             \
    X(epoxy_glPolygonMode)                                                                                             \
    X(epoxy_glPolygonOffset)                                                                                           \
    X(epoxy_glReadBuffer)                                                                                              \
    X(epoxy_glReadPixels)                                                                                              \
    X(epoxy_glRenderbufferStorage)                                                                                     \
    X(epoxy_glRenderbufferStorageMultisample)                                                                          \
    X(epoxy_glScissor)                                                                                                 \
    X(epoxy_glShaderSource)                                                                                            \
    X(epoxy_glTexBuffer)                                                                                               \
    X(epoxy_glTexImage2D)                                                                                              \
    X(epoxy_glTexParameteri)                                                                                           \
    X(epoxy_glUniform1f)                                                                                               \
    X(epoxy_glUniform1fv)                                                                                              \
    X(epoxy_glUniform1i)                                                                                               \
    X(epoxy_glUniform1iv)                                                                                              \
    X(epoxy_glUniform2f)                                                                                               \
    X(epoxy_glUniform3fv)                                                                                              \
    X(epoxy_glUniform4f)                                                                                               \
    X(epoxy_glUniform4fv)                                                                                              \
    X(epoxy_glUniform4i)                                                                                               \
    X(epoxy_glUniformMatrix4fv)                                                                                        \
    X(epoxy_glUnmapBuffer)                                                                                             \
    X(epoxy_glUseProgram)                                                                                              \
    X(epoxy_glVertexAttrib1f)                                                                                          \
    X(epoxy_glVertexAttrib2f)                                                                                          \
    X(epoxy_glVertexAttrib4f)                                                                                          \
    X(epoxy_glVertexAttribI4ui)                                                                                        \
    X(epoxy_glVertexAttribIPointer)                                                                                    \
    X(epoxy_glVertexAttribPointer)                                                                                     \
    X(epoxy_glViewport)

#define RENDER_GL_FUNCTIONS(X) X(epoxy_gl_version) X(epoxy_is_desktop_gl)

#define RENDER_GL_ONE(name) +1
enum { RENDER_GL_SYMBOLS = 0 RENDER_GL_POINTERS(RENDER_GL_ONE) RENDER_GL_FUNCTIONS(RENDER_GL_ONE) };
#undef RENDER_GL_ONE

typedef union render_gl_api {
    struct {
#define RENDER_GL_MEMBER(name) __typeof__(name) *name;
        RENDER_GL_POINTERS(RENDER_GL_MEMBER) /* the address of libepoxy's pointer */
        RENDER_GL_FUNCTIONS(RENDER_GL_MEMBER)
#undef RENDER_GL_MEMBER
    };
    void *symbol[RENDER_GL_SYMBOLS];
} render_gl_api;

/* The loaded symbols: valid once render_gl_load() has succeeded. */
extern const render_gl_api *const render_gl;

/* Loads libepoxy once (thread-safe); false with the reason in `why`. */
bool render_gl_load(char *why, size_t size);

#define epoxy_eglBindAPI (*render_gl->epoxy_eglBindAPI)
#define epoxy_eglChooseConfig (*render_gl->epoxy_eglChooseConfig)
#define epoxy_eglCreateContext (*render_gl->epoxy_eglCreateContext)
#define epoxy_eglDestroyContext (*render_gl->epoxy_eglDestroyContext)
#define epoxy_eglGetDisplay (*render_gl->epoxy_eglGetDisplay)
#define epoxy_eglGetError (*render_gl->epoxy_eglGetError)
#define epoxy_eglGetPlatformDisplayEXT (*render_gl->epoxy_eglGetPlatformDisplayEXT)
#define epoxy_eglInitialize (*render_gl->epoxy_eglInitialize)
#define epoxy_eglMakeCurrent (*render_gl->epoxy_eglMakeCurrent)
#define epoxy_eglQueryDevicesEXT (*render_gl->epoxy_eglQueryDevicesEXT)
#define epoxy_eglQueryString (*render_gl->epoxy_eglQueryString)
#define epoxy_eglReleaseThread (*render_gl->epoxy_eglReleaseThread)
#define epoxy_eglTerminate (*render_gl->epoxy_eglTerminate)
#define epoxy_glActiveTexture (*render_gl->epoxy_glActiveTexture)
#define epoxy_glAttachShader (*render_gl->epoxy_glAttachShader)
#define epoxy_glBindBuffer (*render_gl->epoxy_glBindBuffer)
#define epoxy_glBindFramebuffer (*render_gl->epoxy_glBindFramebuffer)
#define epoxy_glBindRenderbuffer (*render_gl->epoxy_glBindRenderbuffer)
#define epoxy_glBindTexture (*render_gl->epoxy_glBindTexture)
#define epoxy_glBindVertexArray (*render_gl->epoxy_glBindVertexArray)
#define epoxy_glBlendFuncSeparate (*render_gl->epoxy_glBlendFuncSeparate)
#define epoxy_glBlitFramebuffer (*render_gl->epoxy_glBlitFramebuffer)
#define epoxy_glBufferData (*render_gl->epoxy_glBufferData)
#define epoxy_glBufferSubData (*render_gl->epoxy_glBufferSubData)
#define epoxy_glCheckFramebufferStatus (*render_gl->epoxy_glCheckFramebufferStatus)
#define epoxy_glClear (*render_gl->epoxy_glClear)
#define epoxy_glClearColor (*render_gl->epoxy_glClearColor)
#define epoxy_glClearDepth (*render_gl->epoxy_glClearDepth)
#define epoxy_glCompileShader (*render_gl->epoxy_glCompileShader)
#define epoxy_glCreateProgram (*render_gl->epoxy_glCreateProgram)
#define epoxy_glCreateShader (*render_gl->epoxy_glCreateShader)
#define epoxy_glDeleteBuffers (*render_gl->epoxy_glDeleteBuffers)
#define epoxy_glDeleteFramebuffers (*render_gl->epoxy_glDeleteFramebuffers)
#define epoxy_glDeleteProgram (*render_gl->epoxy_glDeleteProgram)
#define epoxy_glDeleteRenderbuffers (*render_gl->epoxy_glDeleteRenderbuffers)
#define epoxy_glDeleteShader (*render_gl->epoxy_glDeleteShader)
#define epoxy_glDeleteTextures (*render_gl->epoxy_glDeleteTextures)
#define epoxy_glDeleteVertexArrays (*render_gl->epoxy_glDeleteVertexArrays)
#define epoxy_glDepthFunc (*render_gl->epoxy_glDepthFunc)
#define epoxy_glDepthMask (*render_gl->epoxy_glDepthMask)
#define epoxy_glDisable (*render_gl->epoxy_glDisable)
#define epoxy_glDrawArrays (*render_gl->epoxy_glDrawArrays)
#define epoxy_glDrawBuffer (*render_gl->epoxy_glDrawBuffer)
#define epoxy_glDrawElements (*render_gl->epoxy_glDrawElements)
#define epoxy_glDrawElementsBaseVertex (*render_gl->epoxy_glDrawElementsBaseVertex)
#define epoxy_glDrawElementsInstanced (*render_gl->epoxy_glDrawElementsInstanced)
#define epoxy_glEnable (*render_gl->epoxy_glEnable)
#define epoxy_glEnableVertexAttribArray (*render_gl->epoxy_glEnableVertexAttribArray)
#define epoxy_glFinish (*render_gl->epoxy_glFinish)
#define epoxy_glFramebufferRenderbuffer (*render_gl->epoxy_glFramebufferRenderbuffer)
#define epoxy_glFramebufferTexture2D (*render_gl->epoxy_glFramebufferTexture2D)
#define epoxy_glGenBuffers (*render_gl->epoxy_glGenBuffers)
#define epoxy_glGenFramebuffers (*render_gl->epoxy_glGenFramebuffers)
#define epoxy_glGenRenderbuffers (*render_gl->epoxy_glGenRenderbuffers)
#define epoxy_glGenTextures (*render_gl->epoxy_glGenTextures)
#define epoxy_glGenVertexArrays (*render_gl->epoxy_glGenVertexArrays)
#define epoxy_glGenerateMipmap (*render_gl->epoxy_glGenerateMipmap)
#define epoxy_glGetError (*render_gl->epoxy_glGetError)
#define epoxy_glGetIntegerv (*render_gl->epoxy_glGetIntegerv)
#define epoxy_glGetProgramInfoLog (*render_gl->epoxy_glGetProgramInfoLog)
#define epoxy_glGetProgramiv (*render_gl->epoxy_glGetProgramiv)
#define epoxy_glGetShaderInfoLog (*render_gl->epoxy_glGetShaderInfoLog)
#define epoxy_glGetShaderiv (*render_gl->epoxy_glGetShaderiv)
#define epoxy_glGetString (*render_gl->epoxy_glGetString)
#define epoxy_glGetUniformLocation (*render_gl->epoxy_glGetUniformLocation)
#define epoxy_glLinkProgram (*render_gl->epoxy_glLinkProgram)
#define epoxy_glMapBufferRange (*render_gl->epoxy_glMapBufferRange)
#define epoxy_glPixelStorei (*render_gl->epoxy_glPixelStorei)
#define epoxy_glPolygonMode (*render_gl->epoxy_glPolygonMode)
#define epoxy_glPolygonOffset (*render_gl->epoxy_glPolygonOffset)
#define epoxy_glReadBuffer (*render_gl->epoxy_glReadBuffer)
#define epoxy_glReadPixels (*render_gl->epoxy_glReadPixels)
#define epoxy_glRenderbufferStorage (*render_gl->epoxy_glRenderbufferStorage)
#define epoxy_glRenderbufferStorageMultisample (*render_gl->epoxy_glRenderbufferStorageMultisample)
#define epoxy_glScissor (*render_gl->epoxy_glScissor)
#define epoxy_glShaderSource (*render_gl->epoxy_glShaderSource)
#define epoxy_glTexBuffer (*render_gl->epoxy_glTexBuffer)
#define epoxy_glTexImage2D (*render_gl->epoxy_glTexImage2D)
#define epoxy_glTexParameteri (*render_gl->epoxy_glTexParameteri)
#define epoxy_glUniform1f (*render_gl->epoxy_glUniform1f)
#define epoxy_glUniform1fv (*render_gl->epoxy_glUniform1fv)
#define epoxy_glUniform1i (*render_gl->epoxy_glUniform1i)
#define epoxy_glUniform1iv (*render_gl->epoxy_glUniform1iv)
#define epoxy_glUniform2f (*render_gl->epoxy_glUniform2f)
#define epoxy_glUniform3fv (*render_gl->epoxy_glUniform3fv)
#define epoxy_glUniform4f (*render_gl->epoxy_glUniform4f)
#define epoxy_glUniform4fv (*render_gl->epoxy_glUniform4fv)
#define epoxy_glUniform4i (*render_gl->epoxy_glUniform4i)
#define epoxy_glUniformMatrix4fv (*render_gl->epoxy_glUniformMatrix4fv)
#define epoxy_glUnmapBuffer (*render_gl->epoxy_glUnmapBuffer)
#define epoxy_glUseProgram (*render_gl->epoxy_glUseProgram)
#define epoxy_glVertexAttrib1f (*render_gl->epoxy_glVertexAttrib1f)
#define epoxy_glVertexAttrib2f (*render_gl->epoxy_glVertexAttrib2f)
#define epoxy_glVertexAttrib4f (*render_gl->epoxy_glVertexAttrib4f)
#define epoxy_glVertexAttribI4ui (*render_gl->epoxy_glVertexAttribI4ui)
#define epoxy_glVertexAttribIPointer (*render_gl->epoxy_glVertexAttribIPointer)
#define epoxy_glVertexAttribPointer (*render_gl->epoxy_glVertexAttribPointer)
#define epoxy_glViewport (*render_gl->epoxy_glViewport)
#define epoxy_gl_version (render_gl->epoxy_gl_version)
#define epoxy_is_desktop_gl (render_gl->epoxy_is_desktop_gl)

#endif
