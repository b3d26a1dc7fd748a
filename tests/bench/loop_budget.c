/* The GL driver's loop budget (not a pass/fail test): one compute invocation
 * runs a loop of BURN iterations, then a loop whose count (10) the compiler
 * cannot see, and reports how many iterations of each ran. On Mesa 22
 * llvmpipe an invocation has 65,535 loop iterations in all, shared by its
 * loops: past them every loop stops after its first iteration, silently.
 * The exact method's shaders pass that budget on lists past the layer cap
 * (docs/EVALUATION.md), which is why their heap and insertion sorts disagree
 * there: each stops at another point.
 *
 *   loop_budget [BURN ...]   (default 60000 65530 66000 200000)
 */
#include <epoxy/gl.h>
#include <stdio.h>
#include <stdlib.h>

#include "gl_context.h"

static const char *const SOURCE = "#version 450\n"
                                  "layout(local_size_x = 1) in;\n"
                                  "layout(std430, binding = 0) buffer Out { uint counts[2]; };\n"
                                  "uniform int u_burn;\n"
                                  "uniform int u_ten;\n"
                                  "void main()\n"
                                  "{\n"
                                  "    for (int i = 0; i < u_burn; i++)\n"
                                  "        counts[0] = uint(i) + 1u;\n"
                                  "    for (int k = 0; k < u_ten; k++)\n"
                                  "        counts[1] = uint(k) + 1u;\n"
                                  "}\n";

int main(int argc, char **argv)
{
    lc_error err = {0};
    lc_gl *gl = NULL;
    lc_gl_desc desc = {.device = -1};
    if (lc_gl_create(&desc, &gl, &err) != 0 || lc_gl_make_current(gl, &err) != 0) {
        fprintf(stderr, "loop_budget: %s\n", err.msg);
        return 1;
    }
    printf("renderer: %s\n", (const char *)glGetString(GL_RENDERER));
    GLuint sh = glCreateShader(GL_COMPUTE_SHADER);
    glShaderSource(sh, 1, &SOURCE, NULL);
    glCompileShader(sh);
    GLuint prog = glCreateProgram();
    glAttachShader(prog, sh);
    glLinkProgram(prog);
    GLint ok = 0;
    glGetProgramiv(prog, GL_LINK_STATUS, &ok);
    if (!ok) {
        fprintf(stderr, "loop_budget: the shader did not link\n");
        return 1;
    }
    GLuint buf;
    glCreateBuffers(1, &buf);
    glNamedBufferStorage(buf, 8, NULL, GL_DYNAMIC_STORAGE_BIT);
    static const int defaults[] = {60000, 65530, 66000, 200000};
    int n = argc > 1 ? argc - 1 : 4;
    for (int i = 0; i < n; i++) {
        int burn = argc > 1 ? atoi(argv[i + 1]) : defaults[i];
        const GLuint zero[2] = {0, 0};
        glNamedBufferSubData(buf, 0, 8, zero);
        glUseProgram(prog);
        glUniform1i(glGetUniformLocation(prog, "u_burn"), burn);
        glUniform1i(glGetUniformLocation(prog, "u_ten"), 10);
        glBindBufferBase(GL_SHADER_STORAGE_BUFFER, 0, buf);
        glDispatchCompute(1, 1, 1);
        glMemoryBarrier(GL_BUFFER_UPDATE_BARRIER_BIT);
        GLuint got[2];
        glGetNamedBufferSubData(buf, 0, 8, got);
        printf("a loop of %d iterations ran %u, the loop of 10 after it ran %u\n", burn, got[0], got[1]);
    }
    lc_gl_destroy(gl);
    return 0;
}
