module.exports = {
  positions: [
    [0, 0, 0], [1, 0, 0], [1, 1, 0]
  ],
  cells: [
    [0, 1, 2]
  ]
}
