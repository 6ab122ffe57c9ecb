#version 330 core
// Shadow pass: only the depth (the height of the first surface along each
// light ray) is written; the viewport is exactly one cell of light-oblique
// coordinates, so clipping keeps only that cell.
void main()
{
}
